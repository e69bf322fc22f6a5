//! The members of a sweep and their job files. A member is a variant × record × intensity; its
//! job file is the base job with the record, the scale, the law files, the duration and the
//! results folder replaced, every path made absolute. It runs alone as it stands
//! (`mpirun -n <group_size> masonry-hpc <results>/jobs/<member>.toml`, the sweep's results of the
//! member moved aside to `<member>.previous`), and the sweep runs it from the same file.
use super::{AnalysisConfig, FileError, MaterialConfig, RecordFormat, SweepJob};
use std::path::Path;
use toml::{Table, Value};

/// One member of a sweep.
#[derive(Clone, Debug, PartialEq)]
pub struct Member {
    /// Position in the sweep's order (variant, record, intensity).
    pub index: usize,
    /// Index into `SweepJob::variants`.
    pub variant: usize,
    /// Index into `SweepJob::records`.
    pub record: usize,
    /// Index into `[sweep] intensities` (a grid's member; `None` for the hunt's).
    pub intensity: Option<usize>,
    /// Folder name: `<variant>-<record>-<measure><intensity>`.
    pub name: String,
    /// The intensity [m/s²].
    pub level: f64,
    /// The factor on the record as written.
    pub factor: f64,
}

impl SweepJob {
    /// Every member of a grid, in the order variant, record, intensity (none for a hunt: its
    /// members are decided as it runs).
    pub fn members(&self) -> Vec<Member> {
        let grid = match self.intensities() {
            super::Intensities::Grid(x) => x,
            super::Intensities::Hunt(_) => &[],
        };
        let mut out = Vec::new();
        for v in 0..self.variants.len() {
            for r in 0..self.records.len() {
                for (i, &x) in grid.iter().enumerate() {
                    out.push(self.member(out.len(), v, r, x, Some(i)));
                }
            }
        }
        out
    }

    /// Member number `index` of variant `v`, record `r` at intensity `x` (grid position `grid`).
    pub fn member(&self, index: usize, v: usize, r: usize, x: f64, grid: Option<usize>) -> Member {
        let (variant, record) = (&self.variants[v], &self.records[r]);
        Member {
            index,
            variant: v,
            record: r,
            intensity: grid,
            name: format!("{}-{}-{}{:.4}", variant.name, record.name, self.spec.sweep.scale_by.file_tag(), x),
            level: x,
            factor: self.factor(record, x),
        }
    }

    /// The job file of member `m` with its results in `dir`: the base job's text with the record,
    /// scale, law files, duration and results folder replaced and every path absolute.
    pub fn member_job_text(&self, m: &Member, dir: &Path) -> Result<String, FileError> {
        let invalid = |reason: String| FileError::Invalid { file: self.base_file.clone(), reason };
        let mut t: Table = toml::from_str(&self.base_text).map_err(|e| invalid(e.to_string()))?;
        let path = |p: &Path| Value::String(p.display().to_string());

        if let Some(mesh) = sub(&mut t, "mesh") {
            mesh.insert("file".into(), path(&self.base.mesh_file));
        }
        let variant = &self.variants[m.variant];
        if let Some(mats) = sub(&mut t, "materials") {
            for (name, cfg) in &self.base.spec.materials {
                if let (MaterialConfig::Damage(d), Some(entry)) =
                    (cfg, mats.get_mut(name).and_then(Value::as_table_mut))
                {
                    if let Some(file) = variant.law_file.as_ref().or(d.law_file.as_ref()) {
                        if d.law_file.is_some() {
                            entry.insert("law_file".into(), path(file));
                        }
                    }
                }
            }
        }
        if let AnalysisConfig::SeismicAssessment(a) = &self.base.spec.analysis {
            if let (Some(shapes), Some(u)) = (
                a.updating.as_ref().and_then(|u| u.target_shapes.as_ref()),
                sub(&mut t, "analysis").and_then(|a| a.get_mut("updating")).and_then(Value::as_table_mut),
            ) {
                u.insert("target_shapes".into(), path(shapes));
            }
        }
        let record = &self.records[m.record];
        let dynamics = sub(&mut t, "dynamics").ok_or_else(|| invalid("no [dynamics]".into()))?;
        if let Some(d) = self.spec.sweep.duration {
            dynamics.insert("duration".into(), Value::Float(d));
        }
        if let Some(band) = self.base.spec.dynamics.as_ref().and_then(|d| d.convergence.as_ref()) {
            dynamics.insert("convergence".into(), path(band));
        }
        if matches!(self.intensities(), super::Intensities::Hunt(h) if h.stop_at_passage) {
            // `[sweep.hunt] stop_at_passage`: the limits end the member's run once all are passed.
            let rules = self.spec.sweep.limit.iter().map(|l| {
                let mut r = Table::new();
                r.insert("group".into(), Value::String(l.group.clone()));
                r.insert("share".into(), Value::Float(l.share));
                Value::Table(r)
            });
            dynamics.insert("stop_when".into(), Value::Array(rules.collect()));
        }
        let components = dynamics
            .get_mut("ground_motion")
            .and_then(Value::as_array_mut)
            .ok_or_else(|| invalid("no [[dynamics.ground_motion]]".into()))?;
        for g in components.iter_mut() {
            let g = g.as_table_mut().ok_or_else(|| invalid("a ground motion is not a table".into()))?;
            let scale = match g.get("scale") {
                Some(Value::Float(x)) => *x,
                Some(Value::Integer(x)) => *x as f64,
                _ => 1.0,
            };
            for k in ["synthetic", "units", "dt"] {
                g.remove(k);
            }
            g.insert("file".into(), path(&record.file));
            g.insert("format".into(), Value::String(format_name(record.format).into()));
            if let Some(u) = &record.units {
                g.insert("units".into(), Value::String(u.clone()));
            }
            if let Some(dt) = record.dt {
                g.insert("dt".into(), Value::Float(dt));
            }
            g.insert("scale".into(), Value::Float(scale * m.factor));
        }
        let title = self.base.spec.title.as_deref().unwrap_or("");
        t.insert("title".into(), Value::String(format!("{title} (sweep member {})", m.name)));
        let mut output = Table::new();
        output.insert("dir".into(), path(dir));
        output.insert("existing".into(), Value::String("backup".into()));
        t.insert("output".into(), Value::Table(output));

        let body = toml::to_string(&t).map_err(|e| invalid(format!("member {}: {e}", m.name)))?;
        Ok(format!(
            "# Member {} of the sweep {}: {} ({}) scaled by {:.6} to {} = {} m/s², material {}.\n\
             # Runs alone as it stands: mpirun -n {} masonry-hpc <this file>\n{body}",
            m.name,
            self.source.file.display(),
            record.name,
            record.file.display(),
            m.factor,
            self.spec.sweep.scale_by.label(),
            m.level,
            variant.law_file.as_ref().map_or_else(|| "of the base job".to_string(), |f| f.display().to_string()),
            self.spec.analysis.group_size,
        ))
    }
}

/// The table at key `k` of `t`, if it is one.
fn sub<'t>(t: &'t mut Table, k: &str) -> Option<&'t mut Table> {
    t.get_mut(k).and_then(Value::as_table_mut)
}

/// The `format` key's value of a record format.
fn format_name(f: RecordFormat) -> &'static str {
    match f {
        RecordFormat::At2 => "at2",
        RecordFormat::Esm => "esm",
        RecordFormat::TwoColumn => "two_column",
        RecordFormat::OneColumn => "one_column",
    }
}

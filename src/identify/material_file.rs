//! The material file the identification writes and structural jobs read by path
//! (`[materials.NAME] type = "damage", law_file = "…"`): a TOML file whose `[law]` table is the
//! damage law's parameters (`material::DamageParams`, the same keys as an inline material) and
//! whose `[provenance]` table says where they come from (ignored by the reader).
use crate::material::DamageParams;
use serde::Serialize;
use std::path::Path;

/// Where the law comes from.
#[derive(Clone, Debug, Serialize)]
pub struct Provenance {
    /// The identification job file.
    pub job: String,
    /// What was fitted (a sentence).
    pub method: String,
    /// Element size h [m] used to turn B_t into G_f (Hillerborg).
    pub element_size: f64,
    /// Final error (the measure's value) in tension and compression.
    pub error_tension: f64,
    /// Compression error.
    pub error_compression: f64,
    /// The error measure.
    pub error_measure: String,
    /// The DEM parameters the virtual tests used.
    pub dem: Option<super::dem_adapter::DemParameters>,
}

#[derive(Serialize)]
struct MaterialFile<'a> {
    law: &'a DamageParams,
    provenance: &'a Provenance,
}

/// The file's text.
pub fn material_toml(law: &DamageParams, provenance: &Provenance) -> Result<String, String> {
    let body = toml::to_string(&MaterialFile { law, provenance }).map_err(|e| e.to_string())?;
    Ok(format!(
        "# Masonry damage law identified from DEM virtual tests (masonry-hpc identification).\n\
         # Reference it from a structural job: [materials.masonry] type = \"damage\", law_file = \"<this file>\"\n{body}"
    ))
}

/// Writes the file.
pub fn write_material_file(file: &Path, law: &DamageParams, provenance: &Provenance) -> Result<(), String> {
    let text = material_toml(law, provenance)?;
    std::fs::write(file, text).map_err(|e| format!("cannot write {}: {e}", file.display()))
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::material::Regularization;

    #[test]
    fn law_table_reads_back() {
        let law = DamageParams {
            e: 2.885e9,
            nu: 0.19,
            eps0_t: 1.1e-4,
            eps0_c: 3e-4,
            gf_t: 40.0,
            a_c: 0.7,
            b_c: 900.0,
            gf_c: None,
            regularization: Regularization::HillerborgNoElastic,
        };
        let p = Provenance {
            job: "j.toml".into(),
            method: "m".into(),
            element_size: 1.2,
            error_tension: 0.1,
            error_compression: 0.2,
            error_measure: "eq15".into(),
            dem: None,
        };
        let text = material_toml(&law, &p).unwrap();
        #[derive(serde::Deserialize)]
        struct F {
            law: DamageParams,
        }
        let back: F = toml::from_str(&text).unwrap();
        assert_eq!(back.law, law);
    }
}

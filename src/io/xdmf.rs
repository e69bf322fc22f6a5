//! The XDMF 3 index: XML text that tells ParaView and meshio where the heavy data lives in the HDF5
//! file.
//!
//! Layout (chosen so that ParaView 5.11 and `meshio.xdmf.TimeSeriesReader` both read it):
//! ```text
//! Xdmf Version="3.0"
//! └ Domain
//!   └ Grid "results"  Collection / Temporal        (before the first step: a single Uniform "mesh")
//!     ├ Grid "step_0" Uniform: Time, Topology, Geometry, mesh attributes, step-0 fields
//!     └ Grid "step_1" ...
//! ```
//! Every step grid repeats the Topology and Geometry *elements*, but they reference the same HDF5
//! datasets (`/mesh/topology`, `/mesh/coordinates`): nothing heavy is copied. This avoids XInclude,
//! which meshio's reader does not resolve (it takes the mesh from the first grid of the collection).
//!
//! Times are written with Rust's shortest round-trip formatting (`{:?}`), so `float(text)` gives
//! back the exact `f64`.
//!
//! **Restarts.** A restarted time history writes its steps to an HDF5 file of its own and
//! continues the run's index: the steps up to the checkpoint keep pointing at the earlier files
//! (each step grid names its file), so ParaView opens the whole run as one series. The earlier
//! steps are read back from the index by [`read_steps`], which reads the layout [`XdmfIndex::render`]
//! writes (one element per line), nothing more general.

use std::fmt::Write as _;
use std::path::Path;

/// Where a field lives on the mesh.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub(crate) enum Center {
    /// One value (tuple) per node.
    Node,
    /// One value (tuple) per cell.
    Cell,
}

/// The stored number type of a dataset.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub(crate) enum Number {
    /// IEEE double.
    F64,
    /// 32-bit signed integer.
    I32,
    /// 64-bit unsigned integer.
    U64,
}

impl Number {
    /// XDMF `NumberType` and `Precision`.
    fn xdmf(self) -> (&'static str, u8) {
        match self {
            Number::F64 => ("Float", 8),
            Number::I32 => ("Int", 4),
            Number::U64 => ("UInt", 8),
        }
    }
}

/// One attribute of a grid: a named dataset in the HDF5 file.
#[derive(Clone, Debug, PartialEq)]
pub(crate) struct FieldRef {
    /// Attribute name shown by the readers.
    pub name: String,
    /// Node or cell field.
    pub center: Center,
    /// Components per node or cell (1 scalar, 3 vector, other matrix with `n_comp` columns).
    pub n_comp: usize,
    /// Stored number type.
    pub number: Number,
    /// HDF5 path of the dataset, e.g. `/steps/0/displacement`.
    pub h5_path: String,
}

/// One completed output step.
#[derive(Clone, Debug, PartialEq)]
pub(crate) struct StepRef {
    /// Its time.
    pub time: f64,
    /// Its fields, in the order written.
    pub fields: Vec<FieldRef>,
    /// The HDF5 file that holds the step and its mesh, when it is not the index's own (the steps
    /// a restarted run keeps from before its restart).
    pub h5_name: Option<String>,
}

/// Everything the XDMF index says.
#[derive(Clone, Debug, PartialEq)]
pub(crate) struct XdmfIndex {
    /// The HDF5 file name, relative to the XDMF file's directory.
    pub h5_name: String,
    /// Number of nodes.
    pub n_nodes: usize,
    /// Number of cells.
    pub n_cells: usize,
    /// Length of the Mixed topology array.
    pub topology_len: usize,
    /// Attributes of the mesh itself, repeated in every step (group, ids, cell types).
    pub mesh_fields: Vec<FieldRef>,
    /// Completed steps.
    pub steps: Vec<StepRef>,
}

/// Escapes the five XML special characters for use in attribute values and text.
pub(crate) fn xml_escape(s: &str) -> String {
    let mut out = String::with_capacity(s.len());
    for ch in s.chars() {
        match ch {
            '&' => out.push_str("&amp;"),
            '<' => out.push_str("&lt;"),
            '>' => out.push_str("&gt;"),
            '"' => out.push_str("&quot;"),
            '\'' => out.push_str("&apos;"),
            c => out.push(c),
        }
    }
    out
}

impl XdmfIndex {
    /// The index of a new file: the mesh of `n_nodes` nodes and `n_cells` cells (mixed topology
    /// of `topology_len` entries) with its id, group and type fields, no step yet.
    pub(crate) fn for_mesh(h5_name: String, n_nodes: usize, n_cells: usize, topology_len: usize) -> XdmfIndex {
        let field = |name: &str, center, number, h5_path: &str| FieldRef {
            name: name.into(),
            center,
            n_comp: 1,
            number,
            h5_path: h5_path.into(),
        };
        XdmfIndex {
            h5_name,
            n_nodes,
            n_cells,
            topology_len,
            mesh_fields: vec![
                field("node_id", Center::Node, Number::U64, "/mesh/node_ids"),
                field("cell_id", Center::Cell, Number::U64, "/mesh/cell_ids"),
                field("group", Center::Cell, Number::I32, "/mesh/cell_group"),
                field("gmsh_type", Center::Cell, Number::I32, "/mesh/cell_types"),
            ],
            steps: Vec::new(),
        }
    }

    /// The XML text (UTF-8, one element per line).
    pub(crate) fn render(&self) -> String {
        let mut s = String::new();
        s.push_str("<?xml version=\"1.0\" encoding=\"utf-8\"?>\n");
        s.push_str("<Xdmf Version=\"3.0\" xmlns:xi=\"http://www.w3.org/2001/XInclude\">\n");
        s.push_str("  <Domain>\n");
        if self.steps.is_empty() {
            s.push_str("    <Grid Name=\"mesh\" GridType=\"Uniform\">\n");
            self.push_mesh(&mut s, "      ", &self.h5_name);
            s.push_str("    </Grid>\n");
        } else {
            s.push_str("    <Grid Name=\"results\" GridType=\"Collection\" CollectionType=\"Temporal\">\n");
            for (k, step) in self.steps.iter().enumerate() {
                let h5 = step.h5_name.as_deref().unwrap_or(&self.h5_name);
                let _ = writeln!(s, "      <Grid Name=\"step_{k}\" GridType=\"Uniform\">");
                let _ = writeln!(s, "        <Time Value=\"{:?}\"/>", step.time);
                self.push_mesh(&mut s, "        ", h5);
                for f in &step.fields {
                    self.push_attribute(&mut s, "        ", f, h5);
                }
                s.push_str("      </Grid>\n");
            }
            s.push_str("    </Grid>\n");
        }
        s.push_str("  </Domain>\n</Xdmf>\n");
        s
    }

    /// Topology, geometry and the mesh attributes, in the HDF5 file `h5_name`.
    fn push_mesh(&self, s: &mut String, ind: &str, h5_name: &str) {
        let h5 = xml_escape(h5_name);
        let _ = writeln!(s, "{ind}<Topology TopologyType=\"Mixed\" NumberOfElements=\"{}\">", self.n_cells);
        let _ = writeln!(
            s,
            "{ind}  <DataItem Dimensions=\"{}\" NumberType=\"Int\" Precision=\"8\" \
             Format=\"HDF\">{h5}:/mesh/topology</DataItem>",
            self.topology_len
        );
        let _ = writeln!(s, "{ind}</Topology>");
        let _ = writeln!(s, "{ind}<Geometry GeometryType=\"XYZ\">");
        let _ = writeln!(
            s,
            "{ind}  <DataItem Dimensions=\"{} 3\" NumberType=\"Float\" Precision=\"8\" \
             Format=\"HDF\">{h5}:/mesh/coordinates</DataItem>",
            self.n_nodes
        );
        let _ = writeln!(s, "{ind}</Geometry>");
        for f in &self.mesh_fields {
            self.push_attribute(s, ind, f, h5_name);
        }
    }

    /// One `<Attribute>` with its data item in the HDF5 file `h5_name`.
    fn push_attribute(&self, s: &mut String, ind: &str, f: &FieldRef, h5_name: &str) {
        let (center, rows) = match f.center {
            Center::Node => ("Node", self.n_nodes),
            Center::Cell => ("Cell", self.n_cells),
        };
        let (kind, dims) = match f.n_comp {
            1 => ("Scalar", format!("{rows}")),
            3 => ("Vector", format!("{rows} 3")),
            n => ("Matrix", format!("{rows} {n}")),
        };
        let (number, precision) = f.number.xdmf();
        let _ = writeln!(
            s,
            "{ind}<Attribute Name=\"{}\" AttributeType=\"{kind}\" Center=\"{center}\">",
            xml_escape(&f.name)
        );
        let _ = writeln!(
            s,
            "{ind}  <DataItem Dimensions=\"{dims}\" NumberType=\"{number}\" Precision=\"{precision}\" \
             Format=\"HDF\">{}:{}</DataItem>",
            xml_escape(h5_name),
            xml_escape(&f.h5_path)
        );
        let _ = writeln!(s, "{ind}</Attribute>");
    }
}

/// What an index says about the run so far: its mesh's sizes and its steps, each with the HDF5
/// file that holds it.
#[derive(Clone, Debug, PartialEq)]
pub(crate) struct IndexedSteps {
    /// Number of nodes.
    pub n_nodes: usize,
    /// Number of cells.
    pub n_cells: usize,
    /// Length of the Mixed topology array.
    pub topology_len: usize,
    /// The steps, in order, each with `h5_name` set.
    pub steps: Vec<StepRef>,
}

/// A line of an XDMF index that does not have the layout [`XdmfIndex::render`] writes.
#[derive(Debug, PartialEq, thiserror::Error)]
#[error("line {line}: {expected}: {text}")]
pub(crate) struct BadLine {
    /// 1-based line number.
    line: usize,
    /// What was expected there.
    expected: &'static str,
    /// The line.
    text: String,
}

/// The steps of an index written by [`XdmfIndex::render`] (module docs, "Restarts"). Errors: a
/// line that does not have the layout `render` writes, a step without time or file.
pub(crate) fn read_steps(text: &str) -> Result<IndexedSteps, BadLine> {
    let mut out = IndexedSteps { n_nodes: 0, n_cells: 0, topology_len: 0, steps: Vec::new() };
    let mut step: Option<StepRef> = None;
    // The element whose data item comes next: topology, geometry, or an attribute (name, center).
    let mut pending: Option<Option<(String, Center)>> = None;
    let mut in_topology = false;
    for (n, line) in text.lines().enumerate() {
        let at = |expected: &'static str| BadLine { line: n + 1, expected, text: line.trim().to_string() };
        let l = line.trim();
        if l.starts_with("<Grid Name=\"step_") {
            step = Some(StepRef { time: f64::NAN, fields: Vec::new(), h5_name: None });
        } else if let Some(v) = l.strip_prefix("<Time Value=\"") {
            let t = v.split('"').next().and_then(|x| x.parse::<f64>().ok()).ok_or_else(|| at("a time"))?;
            step.as_mut().ok_or_else(|| at("a time outside a step"))?.time = t;
        } else if l.starts_with("<Topology ") {
            out.n_cells = attribute(l, "NumberOfElements").and_then(|x| x.parse().ok()).ok_or_else(|| at("cells"))?;
            (pending, in_topology) = (Some(None), true);
        } else if l.starts_with("<Geometry ") {
            (pending, in_topology) = (Some(None), false);
        } else if l.starts_with("<Attribute ") {
            let name = attribute(l, "Name").map(xml_unescape).ok_or_else(|| at("an attribute name"))?;
            let center = match attribute(l, "Center") {
                Some("Node") => Center::Node,
                Some("Cell") => Center::Cell,
                _ => return Err(at("a center")),
            };
            pending = Some(Some((name, center)));
        } else if l.starts_with("<DataItem ") {
            let item = data_item(l).ok_or_else(|| at("a data item"))?;
            match pending.take() {
                Some(None) if in_topology => {
                    out.topology_len = item.dims[0];
                    in_topology = false;
                    if let Some(s) = step.as_mut() {
                        s.h5_name = Some(item.file);
                    }
                }
                Some(None) => out.n_nodes = item.dims[0],
                Some(Some((name, center))) if !item.path.starts_with("/mesh/") => {
                    let s = step.as_mut().ok_or_else(|| at("a field outside a step"))?;
                    let n_comp = item.dims.get(1).copied().unwrap_or(1);
                    s.fields.push(FieldRef { name, center, n_comp, number: item.number, h5_path: item.path });
                }
                Some(Some(_)) => {} // a mesh field: the writer adds its own
                None => return Err(at("a data item outside a topology, geometry or attribute")),
            }
        } else if l == "</Grid>" {
            if let Some(s) = step.take() {
                if s.time.is_nan() || s.h5_name.is_none() {
                    return Err(at("a step without its time or its file"));
                }
                out.steps.push(s);
            }
        }
    }
    Ok(out)
}

/// A data item: its dimensions, number type, file and dataset path.
struct DataItem {
    dims: Vec<usize>,
    number: Number,
    file: String,
    path: String,
}

/// `<DataItem Dimensions=".." NumberType=".." Precision=".." Format="HDF">file:/path</DataItem>`.
fn data_item(l: &str) -> Option<DataItem> {
    let dims = attribute(l, "Dimensions")?.split_whitespace().map(|d| d.parse().ok()).collect::<Option<Vec<_>>>()?;
    let number = match (attribute(l, "NumberType")?, attribute(l, "Precision")?) {
        ("Float", "8") => Number::F64,
        ("Int", "4") => Number::I32,
        ("UInt", "8") => Number::U64,
        ("Int", "8") => Number::I32, // the topology's; its number type is not kept
        _ => return None,
    };
    let text = l.split_once('>')?.1.strip_suffix("</DataItem>")?;
    let (file, path) = text.rsplit_once(":/")?;
    (!dims.is_empty()).then(|| DataItem {
        dims,
        number,
        file: xml_unescape(file),
        path: format!("/{}", xml_unescape(path)),
    })
}

/// The value of the XML attribute `key` in the start tag `l` (escaped as written).
fn attribute<'l>(l: &'l str, key: &str) -> Option<&'l str> {
    let pat = format!(" {key}=\"");
    let start = l.find(&pat)? + pat.len();
    l[start..].split('"').next()
}

/// Undoes [`xml_escape`].
fn xml_unescape(s: &str) -> String {
    s.replace("&lt;", "<").replace("&gt;", ">").replace("&quot;", "\"").replace("&apos;", "'").replace("&amp;", "&")
}

/// Writes `text` to `path` atomically: a temporary file in the same directory, flushed to disk,
/// then renamed over `path` (rename is atomic within one file system), so a reader or a killed run
/// never sees a half-written index.
pub(crate) fn write_atomic(path: &Path, text: &str) -> std::io::Result<()> {
    use std::io::Write as _;
    let name = path.file_name().map(|n| n.to_string_lossy().into_owned()).unwrap_or_default();
    let tmp = path.with_file_name(format!(".{name}.tmp"));
    {
        let mut f = std::fs::File::create(&tmp)?;
        f.write_all(text.as_bytes())?;
        f.sync_all()?;
    }
    std::fs::rename(&tmp, path)
}

#[cfg(test)]
mod tests {
    use super::*;

    fn index() -> XdmfIndex {
        XdmfIndex {
            h5_name: "run.h5".into(),
            n_nodes: 9,
            n_cells: 4,
            topology_len: 20,
            mesh_fields: vec![FieldRef {
                name: "group".into(),
                center: Center::Cell,
                n_comp: 1,
                number: Number::I32,
                h5_path: "/mesh/cell_group".into(),
            }],
            steps: vec![],
        }
    }

    #[test]
    fn mesh_only_index_is_one_uniform_grid() {
        let t = index().render();
        assert!(t.contains("<Grid Name=\"mesh\" GridType=\"Uniform\">"));
        assert!(!t.contains("Temporal"));
        assert!(t.contains("<Topology TopologyType=\"Mixed\" NumberOfElements=\"4\">"));
        assert!(t.contains("Dimensions=\"20\" NumberType=\"Int\" Precision=\"8\""));
        assert!(t.contains(">run.h5:/mesh/coordinates</DataItem>"));
        assert!(
            t.contains("Dimensions=\"4\" NumberType=\"Int\" Precision=\"4\" Format=\"HDF\">run.h5:/mesh/cell_group")
        );
    }

    #[test]
    fn steps_reference_the_same_mesh_and_keep_times_exact() {
        let mut x = index();
        // 0.1 + 0.2 = 0.30000000000000004 in binary64: the text must give back the same bits.
        let times = [0.0, 0.1 + 0.2, 1.0e-7];
        for (k, &time) in times.iter().enumerate() {
            x.steps.push(StepRef {
                time,
                h5_name: None,
                fields: vec![
                    FieldRef {
                        name: "u".into(),
                        center: Center::Node,
                        n_comp: 3,
                        number: Number::F64,
                        h5_path: format!("/steps/{k}/u"),
                    },
                    FieldRef {
                        name: "s<6>".into(),
                        center: Center::Cell,
                        n_comp: 6,
                        number: Number::F64,
                        h5_path: format!("/steps/{k}/s<6>"),
                    },
                ],
            });
        }
        let t = x.render();
        assert!(t.contains("CollectionType=\"Temporal\""));
        assert_eq!(t.matches(":/mesh/topology<").count(), 3);
        assert_eq!(t.matches(":/mesh/coordinates<").count(), 3);
        assert!(t.contains("AttributeType=\"Vector\" Center=\"Node\""));
        assert!(t.contains("Dimensions=\"9 3\" NumberType=\"Float\" Precision=\"8\" Format=\"HDF\">run.h5:/steps/2/u<"));
        assert!(t.contains("<Attribute Name=\"s&lt;6&gt;\" AttributeType=\"Matrix\" Center=\"Cell\">"));
        assert!(t.contains("Dimensions=\"4 6\""));
        let parsed: Vec<f64> = t
            .split("<Time Value=\"")
            .skip(1)
            .map(|rest| rest.split('"').next().unwrap_or("").parse::<f64>().unwrap_or(f64::NAN))
            .collect();
        assert_eq!(parsed.len(), 3);
        for (p, e) in parsed.iter().zip(times) {
            assert_eq!(p.to_bits(), e.to_bits(), "time {e} printed as {p}");
        }
        assert_eq!(t.matches("<Grid").count(), t.matches("</Grid>").count());
    }

    #[test]
    fn an_index_reads_back_as_its_steps_with_their_files() {
        // What a restarted run keeps: every step of a rendered index, its time to the bit, its
        // fields (names escaped and back, centre, components, number type, path) and its file:
        // the index's own for new steps, another one for steps kept from before a restart.
        let mut x = index();
        let field = |k: usize, name: &str, center, n_comp, number| FieldRef {
            name: name.into(),
            center,
            n_comp,
            number,
            h5_path: format!("/steps/{k}/{name}"),
        };
        for (k, (time, file)) in [(0.0, Some("run-0.h5")), (0.1 + 0.2, None)].into_iter().enumerate() {
            x.steps.push(StepRef {
                time,
                h5_name: file.map(String::from),
                fields: vec![
                    field(k, "u", Center::Node, 3, Number::F64),
                    field(k, "s<6>", Center::Cell, 6, Number::F64),
                    field(k, "d", Center::Cell, 1, Number::F64),
                ],
            });
        }
        let read = read_steps(&x.render()).unwrap();
        assert_eq!((read.n_nodes, read.n_cells, read.topology_len), (9, 4, 20));
        assert_eq!(read.steps.len(), 2);
        for (r, w) in read.steps.iter().zip(&x.steps) {
            assert_eq!(r.time.to_bits(), w.time.to_bits());
            assert_eq!(r.fields, w.fields);
        }
        assert_eq!(read.steps[0].h5_name.as_deref(), Some("run-0.h5"));
        assert_eq!(read.steps[1].h5_name.as_deref(), Some("run.h5"));
        // Rendered again with the steps read back, the index is the same text.
        let mut y = index();
        y.steps = read.steps.clone();
        y.steps[1].h5_name = None;
        assert_eq!(y.render(), x.render());
        // A broken line is named.
        let bad = x.render().replacen("<Time Value=\"0.0\"/>", "<Time Value=\"zero\"/>", 1);
        let e = read_steps(&bad).unwrap_err().to_string();
        assert!(e.contains("a time") && e.starts_with("line "), "{e}");
    }

    #[test]
    fn atomic_write_replaces_the_file() {
        let dir = std::env::temp_dir().join(format!("masonry_xdmf_{}", std::process::id()));
        std::fs::create_dir_all(&dir).unwrap();
        let p = dir.join("a.xdmf");
        write_atomic(&p, "one").unwrap();
        write_atomic(&p, "two").unwrap();
        assert_eq!(std::fs::read_to_string(&p).unwrap(), "two");
        assert!(!dir.join(".a.xdmf.tmp").exists());
        std::fs::remove_dir_all(&dir).unwrap();
    }
}

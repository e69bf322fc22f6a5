//! Tests of the MSH reader on the hand-written fixtures of `tests/data/msh/` (see
//! `make_binary_fixture.py` there for the binary ones), on the demo tower mesh, on every error
//! case, and on truncated and garbled input (which must give `Err`, never a panic).

use super::*;
use crate::mesh::{CellKind, GroupError, PhysicalGroup};
use std::path::PathBuf;

const PORTAL: &str = include_str!("../../../tests/data/msh/portal.msh");
const PLATE: &str = include_str!("../../../tests/data/msh/plate.msh");
const PORTAL_BIN: &[u8] = include_bytes!("../../../tests/data/msh/portal_binary.msh");

fn fixture(name: &str) -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR")).join("tests/data/msh").join(name)
}

fn read(path: &Path) -> Mesh {
    read_msh(path).unwrap_or_else(|e| panic!("{e}"))
}

/// The error message of parsing `text` (named `t.msh`), which must fail.
fn err(text: &str) -> String {
    parse_msh(text.as_bytes(), "t.msh").expect_err("the input must be rejected").to_string()
}

/// `PORTAL` with `from` (which must occur exactly once) replaced by `to`.
fn portal_with(from: &str, to: &str) -> String {
    assert_eq!(PORTAL.matches(from).count(), 1, "{from:?} must occur once in portal.msh");
    PORTAL.replacen(from, to, 1)
}

/// The 1-based line of `text` on which `needle` (which must occur once) starts.
fn line_of(text: &str, needle: &str) -> usize {
    assert_eq!(text.matches(needle).count(), 1, "{needle:?} must occur once");
    let at = text.find(needle).unwrap_or_default();
    text[..at].matches('\n').count() + 1
}

fn group(dim: u8, tag: i32, name: &str) -> PhysicalGroup {
    PhysicalGroup { dim, tag, name: name.to_string() }
}

#[test]
fn portal_ascii_gives_nodes_cells_and_groups() {
    let m = read(&fixture("portal.msh"));
    // Nodes in order of appearance in portal.msh: the 4 corner points, then one mid-node per curve.
    assert_eq!(m.node_tags, vec![1, 2, 3, 4, 101, 102, 103]);
    assert_eq!(
        m.coords,
        vec![[0., 0., 0.], [0., 0., 3.], [4., 0., 3.], [4., 0., 0.], [0., 0., 1.5], [2., 0., 3.], [4., 0., 1.5]]
    );
    assert_eq!(m.cells.len(), 8);
    assert_eq!(
        (m.cells[0].kind, m.cells[0].tag, &m.cells[0].nodes, m.cells[0].entity),
        (CellKind::Point1, 1, &vec![0], (0, 1))
    );
    assert_eq!(
        (m.cells[1].kind, m.cells[1].tag, &m.cells[1].nodes, m.cells[1].entity),
        (CellKind::Point1, 2, &vec![3], (0, 4))
    );
    // Element 4 joins node tags 101 and 2, i.e. indices 4 and 1.
    assert_eq!(
        (m.cells[3].kind, m.cells[3].tag, &m.cells[3].nodes, m.cells[3].entity),
        (CellKind::Line2, 4, &vec![4, 1], (1, 1))
    );
    assert_eq!(m.groups, vec![group(0, 2, "base"), group(1, 1, "beams")]);
    assert_eq!(m.entity_groups.len(), 7);
    assert_eq!(m.entity_groups[&(0, 1)], vec![2]);
    assert_eq!(m.entity_groups[&(0, 2)], Vec::<i32>::new());
    assert_eq!(m.entity_groups[&(1, 3)], vec![1]);

    let base = m.group("base").unwrap_or_else(|e| panic!("{e}"));
    assert_eq!(m.nodes_in_group(base), vec![0, 3]);
    let beams = m.group("beams").unwrap_or_else(|e| panic!("{e}"));
    assert_eq!(m.cells_in_group(beams).collect::<Vec<_>>(), vec![2, 3, 4, 5, 6, 7]);
    assert_eq!(m.nodes_in_group(beams), (0..7).collect::<Vec<_>>());
}

#[test]
fn portal_binary_files_equal_the_ascii_one() {
    let ascii = read(&fixture("portal.msh"));
    assert_eq!(read(&fixture("portal_binary.msh")), ascii);
    assert_eq!(read(&fixture("portal_binary_be.msh")), ascii);
    // Written by Gmsh 4.15 itself from portal.msh: the same mesh.
    assert_eq!(read(&fixture("portal_gmsh_binary.msh")), ascii);
}

#[test]
fn plate_with_parametric_nodes_gives_a_quad_and_two_triangles() {
    let m = read(&fixture("plate.msh"));
    assert_eq!(m.coords.len(), 6);
    assert_eq!(m.coords[4], [1., 1., 0.]); // the 5th node line "1 1 0 0.5 1": u v are dropped
    let kinds: Vec<_> = m.cells.iter().map(|c| (c.kind, c.nodes.clone())).collect();
    assert_eq!(
        kinds,
        vec![(CellKind::Quad4, vec![0, 1, 4, 3]), (CellKind::Tri3, vec![1, 2, 5]), (CellKind::Tri3, vec![1, 5, 4])]
    );
    let wall = m.group("plate wall").unwrap_or_else(|e| panic!("{e}"));
    assert_eq!(*wall, group(2, 7, "plate wall"));
    assert_eq!(m.cells_in_group(wall).count(), 3);
}

#[test]
fn unknown_group_lists_the_available_names() {
    let m = read(&fixture("portal.msh"));
    let e = m.group("nope").expect_err("no such group");
    assert_eq!(e, GroupError::Unknown { name: "nope".into(), available: vec!["base".into(), "beams".into()] });
    assert_eq!(e.to_string(), "the mesh has no physical group named 'nope'; it has: base, beams");
}

#[test]
fn physical_tags_without_names_become_unnamed_groups() {
    let start = PORTAL.find("$PhysicalNames").unwrap_or_default();
    let end = PORTAL.find("$Entities").unwrap_or_default();
    let text = format!("{}{}", &PORTAL[..start], &PORTAL[end..]);
    let m = parse_msh(text.as_bytes(), "t.msh").unwrap_or_else(|e| panic!("{e}"));
    // Entity order in $Entities: point 1 carries tag 2 (dim 0), curve 1 carries tag 1 (dim 1).
    assert_eq!(m.groups, vec![group(0, 2, ""), group(1, 1, "")]);
    assert_eq!(m.group_names(), vec!["#2 (dim 0)", "#1 (dim 1)"]);
}

#[test]
fn error_io_names_the_file() {
    let e = read_msh(Path::new("/nonexistent/x.msh")).expect_err("missing file");
    assert!(matches!(e, MshError::Io { .. }));
    assert!(e.to_string().starts_with("/nonexistent/x.msh: "), "{e}");
}

#[test]
fn error_not_msh_and_missing_sections() {
    assert_eq!(
        err("hello world\n"),
        "t.msh: not a Gmsh MSH file: it must start with $MeshFormat, found \"hello world\""
    );
    assert_eq!(err(""), "t.msh: not a Gmsh MSH file: it must start with $MeshFormat, found \"\"");
    assert_eq!(
        err("$MeshFormat\n4.1 0 8\n$EndMeshFormat\n"),
        "t.msh: the file has no $Nodes section (a mesh needs $Nodes and $Elements)"
    );
}

#[test]
fn error_version_says_expected_4_1() {
    assert_eq!(
        err(&portal_with("4.1 0 8", "2.2 0 8")),
        "t.msh: line 2: unsupported MSH format version \"2.2\" (expected 4.1)"
    );
    assert_eq!(err(&portal_with("4.1 0 8", "4.1 0 4")), "t.msh: line 2: expected data size 8 in \"4.1 0 4\"");
    assert_eq!(
        err(&portal_with("4.1 0 8", "4.1 2 8")),
        "t.msh: line 2: expected file type 0 (ASCII) or 1 (binary) in \"4.1 2 8\""
    );
}

#[test]
fn error_unsupported_element_type_names_it() {
    let text = portal_with("1 3 1 2\n7 3 103\n8 103 4", "2 1 9 2\n7 1 2 3 4 101 102\n8 1 2 3 4 101 102");
    assert_eq!(
        err(&text),
        format!(
            "t.msh: line {}: unsupported element type: 6-node second order triangle (type 9), element tag 7; \
             supported: 1-node point (type 15), 2-node line (type 1), 3-node triangle (type 2), \
             4-node quadrangle (type 3)",
            line_of(&text, "7 1 2 3")
        )
    );
    let text = portal_with("1 3 1 2\n", "1 3 77 2\n");
    assert!(err(&text).contains("unknown type (type 77), element tag 7;"), "{}", err(&text));
}

#[test]
fn error_dangling_node_reference() {
    let text = portal_with("8 103 4", "8 103 99");
    assert_eq!(
        err(&text),
        format!(
            "t.msh: line {}: element 8 refers to node 99, which $Nodes does not define",
            line_of(&text, "8 103 99")
        )
    );
}

#[test]
fn error_duplicate_node_and_element_tags() {
    let text = portal_with("\n102\n", "\n101\n");
    let line = line_of(&text, "1 2 0 1") + 1; // the tag line follows the block header
    assert_eq!(err(&text), format!("t.msh: line {line}: duplicate node tag 101"));
    let text = portal_with("6 102 3", "5 102 3");
    assert_eq!(err(&text), format!("t.msh: line {}: duplicate element tag 5", line_of(&text, "5 102 3")));
}

#[test]
fn error_truncated_file_names_the_section() {
    let cut = PORTAL.find("101\n0 0 1.5").unwrap_or_default() + 4;
    let text = &PORTAL[..cut];
    let last = text.matches('\n').count() + 1; // the (empty) line after the last line break
    assert_eq!(
        err(text),
        format!("t.msh: line {last}: unexpected end of file while reading section $Nodes (x coordinate)")
    );
    let cut = PORTAL.find("$EndElements").unwrap_or_default();
    assert!(err(&PORTAL[..cut]).contains("unexpected end of file while reading section $Elements (its end marker)"));
    let cut = PORTAL.find("$EndNodeData").unwrap_or_default();
    assert!(err(&PORTAL[..cut]).contains("while reading section $NodeData (skipping to its end marker)"));
}

#[test]
fn error_garbled_numbers() {
    let text = portal_with("\n102\n", "\n1o2\n");
    let line = line_of(&text, "1o2");
    assert_eq!(err(&text), format!("t.msh: line {line}: expected a non-negative integer (node tag), found \"1o2\""));
    let text = portal_with("0 0 1.5", "0 0 1.5.0");
    assert_eq!(
        err(&text),
        format!("t.msh: line {}: expected a finite float (z coordinate), found \"1.5.0\"", line_of(&text, "1.5.0"))
    );
    let text = portal_with("1 1 1 2\n", "1 1 x1 2\n");
    assert_eq!(
        err(&text),
        format!("t.msh: line {}: expected a 32-bit integer (element type), found \"x1\"", line_of(&text, "x1"))
    );
}

#[test]
fn error_counts_that_disagree_with_the_data() {
    let text = portal_with("7 7 1 103", "7 8 1 103");
    assert_eq!(
        err(&text),
        format!("t.msh: line {}: section $Nodes declares 8 nodes but its blocks hold 7", line_of(&text, "7 8 1 103"))
    );
    // One block more than there is: the end marker comes where a block header should.
    let text = portal_with("5 8 1 8", "6 8 1 8");
    assert_eq!(
        err(&text),
        format!(
            "t.msh: line {}: section $Elements ends early: found \"$EndElements\" where entity dimension was \
             expected (the counts in the section disagree with its data)",
            line_of(&text, "$EndElements")
        )
    );
    // Two blocks fewer: data remains where the end marker should be.
    let text = portal_with("5 8 1 8", "3 4 1 8");
    assert_eq!(
        err(&text),
        format!(
            "t.msh: line {}: expected $EndElements after the data of section $Elements, found \"1 2 1 2\" \
             (the counts in the section disagree with its data)",
            line_of(&text, "1 2 1 2")
        )
    );
    let text = portal_with("2\n0 2 \"base\"", "3\n0 2 \"base\"");
    assert!(err(&text).contains("section $PhysicalNames ends early: found \"$EndPhysicalNames\""), "{}", err(&text));
}

#[test]
fn error_element_lines_with_a_wrong_node_count() {
    let text = portal_with("8 103 4", "8 103");
    assert_eq!(
        err(&text),
        format!(
            "t.msh: line {}: element 8 (2-node line) lists 1 of its 2 node tags on its line",
            line_of(&text, "8 103\n")
        )
    );
    let text = portal_with("7 3 103", "7 3 103 4");
    assert_eq!(
        err(&text),
        format!(
            "t.msh: line {}: element 7 (2-node line) has more than 2 node tags on its line",
            line_of(&text, "7 3 103 4")
        )
    );
}

#[test]
fn error_structural_problems() {
    let text = portal_with("1 2 0 1\n", "1 2 2 1\n");
    assert_eq!(
        err(&text),
        format!("t.msh: line {}: parametric flag must be 0 or 1, found 2", line_of(&text, "1 2 2 1"))
    );
    let text = portal_with("1 3 1 2\n", "2 3 1 2\n");
    assert!(err(&text).contains("element type 1 (2-node line) has dimension 1, but its block is of entity dimension 2"));
    let text = portal_with("0 4 15 1", "5 4 15 1");
    assert!(err(&text).contains("entity dimension 5 is not 0, 1, 2 or 3"));
    let text = portal_with("1 1 \"beams\"", "1 1 beams");
    assert!(err(&text).contains("expected a physical name line: dim tag \"name\", found \"1 1 beams\""));
    let text = portal_with("$EndEntities\n", "$EndEntities\n$EndNodes\n");
    assert!(err(&text).contains("expected a section header such as $Nodes, found \"$EndNodes\""));
}

#[test]
fn binary_errors_give_byte_offsets() {
    // Byte 20 holds the int 1 of the byte-order check (after "$MeshFormat\n4.1 1 8\n").
    assert_eq!(&PORTAL_BIN[20..24], &[1, 0, 0, 0]);
    let mut bad = PORTAL_BIN.to_vec();
    bad[20] = 2;
    assert_eq!(
        parse_msh(&bad, "b.msh").expect_err("bad byte order").to_string(),
        "b.msh: byte offset 20: binary byte-order check: expected the int 1, found bytes [2, 0, 0, 0]"
    );
    let nodes = PORTAL_BIN.windows(7).position(|w| w == b"$Nodes\n").unwrap_or_default() + 7;
    // Cut in the middle of the first size_t of $Nodes.
    assert_eq!(
        parse_msh(&PORTAL_BIN[..nodes + 3], "b.msh").expect_err("cut").to_string(),
        format!(
            "b.msh: byte offset {}: unexpected end of file while reading section $Nodes (number of entity blocks)",
            nodes + 3
        )
    );
    // The node tag 103 (little-endian size_t) replaced by 102: a duplicate.
    let tag103 = [103u8, 0, 0, 0, 0, 0, 0, 0];
    let at = PORTAL_BIN.windows(8).rposition(|w| w == tag103).unwrap_or_default();
    let first_elements = PORTAL_BIN.windows(10).position(|w| w == b"$Elements\n").unwrap_or_default();
    let at_node = PORTAL_BIN[..first_elements].windows(8).rposition(|w| w == tag103).unwrap_or_default();
    assert!(at > at_node);
    let mut dup = PORTAL_BIN.to_vec();
    dup[at_node] = 102;
    assert_eq!(
        parse_msh(&dup, "b.msh").expect_err("dup").to_string(),
        format!("b.msh: byte offset {at_node}: duplicate node tag 102")
    );
}

/// A deterministic pseudo-random byte stream (Knuth's MMIX LCG constants).
struct Lcg(u64);
impl Lcg {
    fn next(&mut self) -> u8 {
        self.0 = self.0.wrapping_mul(6364136223846793005).wrapping_add(1442695040888963407);
        (self.0 >> 56) as u8
    }
}

#[test]
fn truncations_at_every_byte_are_errors_never_panics() {
    for (name, data) in [("portal", PORTAL.as_bytes()), ("plate", PLATE.as_bytes()), ("portal_bin", PORTAL_BIN)] {
        let end = data.windows(12).position(|w| w == b"$EndElements").unwrap_or_default() + 12;
        for n in 0..data.len() {
            let r = parse_msh(&data[..n], name);
            if n < end {
                assert!(r.is_err(), "{name} cut at byte {n} must be rejected");
            }
        }
        assert!(parse_msh(data, name).is_ok());
    }
}

#[test]
fn garbage_and_mutated_bytes_are_errors_never_panics() {
    let mut rng = Lcg(42);
    for len in (0..3000).step_by(7) {
        let junk: Vec<u8> = (0..len).map(|_| rng.next()).collect();
        assert!(parse_msh(&junk, "junk").is_err());
        // The same junk behind a valid header, so that the section parsers see it.
        for header in [
            &b"$MeshFormat\n4.1 0 8\n$EndMeshFormat\n$Nodes\n"[..],
            b"$MeshFormat\n4.1 1 8\n\x01\0\0\0\n$EndMeshFormat\n$Elements\n",
        ] {
            let mut d = header.to_vec();
            d.extend_from_slice(&junk);
            assert!(parse_msh(&d, "junk").is_err());
        }
    }
    // Every byte of each fixture replaced by a few troublesome values: any result but a panic.
    for data in [PORTAL.as_bytes(), PLATE.as_bytes(), PORTAL_BIN] {
        for i in 0..data.len() {
            for v in [b'9', b'$', b'\n', b'-', 0xff, 0x7f] {
                let mut d = data.to_vec();
                d[i] = v;
                let _ = parse_msh(&d, "mutant");
            }
        }
    }
}

#[test]
fn demo_tower_mesh_matches_the_generator() {
    let m = read(&Path::new(env!("CARGO_MANIFEST_DIR")).join("meshes/tower.msh"));
    // Printed by `python3 scripts/make_tower_mesh.py` with its default arguments.
    assert_eq!(m.coords.len(), TOWER_NODES);
    assert_eq!(m.cells.iter().filter(|c| c.kind == CellKind::Line2).count(), TOWER_LINES);
    assert_eq!(m.cells.iter().filter(|c| c.kind == CellKind::Point1).count(), 8);
    assert_eq!(m.group_names(), vec!["legs", "girts", "braces", "base", "top"]);
    for (name, dim) in [("legs", 1), ("girts", 1), ("braces", 1), ("base", 0), ("top", 0)] {
        let g = m.group(name).unwrap_or_else(|e| panic!("{e}"));
        assert_eq!(g.dim, dim);
    }
    let base = m.group("base").unwrap_or_else(|e| panic!("{e}"));
    let base_nodes = m.nodes_in_group(base);
    assert_eq!(base_nodes.len(), 4);
    assert!(base_nodes.iter().all(|&n| m.coords[n][2] == 0.0));
    let top = m.group("top").unwrap_or_else(|e| panic!("{e}"));
    let top_nodes = m.nodes_in_group(top);
    assert_eq!(top_nodes.len(), 4);
    assert!(top_nodes.iter().all(|&n| m.coords[n][2] == TOWER_HEIGHT));
    let members: usize = ["legs", "girts", "braces"]
        .iter()
        .map(|n| m.group(n).map(|g| m.cells_in_group(g).count()).unwrap_or_default())
        .sum();
    assert_eq!(members, TOWER_LINES);
}

/// Counts printed by `python3 scripts/make_tower_mesh.py` (defaults: 15 storeys of 6 m, 2 panels,
/// 3 divisions): "1819 nodes, 2348 elements (2340 lines, 8 points)", "height 90 m".
const TOWER_NODES: usize = 1819;
const TOWER_LINES: usize = 2340;
const TOWER_HEIGHT: f64 = 90.0;

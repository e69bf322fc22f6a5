//! Whole-sample tests: tiling, convexity, neighbour symmetry, perpendicular beams, determinism,
//! the paper's wall, a large random sample, bad input, and a drawing.
use super::*;
use crate::dem::polygon::P2;
use std::collections::HashSet;

/// The paper's wall (paper §2.1, Table 1).
fn paper_wall(seed: u64) -> SampleConfig {
    SampleConfig::paper_wall(seed)
}

fn random(n: usize, seed: u64) -> SampleConfig {
    SampleConfig {
        layout: SampleLayout::Random(RandomLayout {
            width: 2.0,
            height: 1.0,
            n_particles: n,
            min_distance_factor: 0.7,
        }),
        thickness: 0.5,
        seed,
        alpha: 0.8,
        facet_tolerance: 0.02,
        tiny_facets: TinyFacetPolicy::Merge,
    }
}

/// Checks every invariant of a built sample.
fn check_invariants(s: &Sample) {
    // Tiling: Σ A_i = W H to 1e-10 relative (exact up to rounding for a conforming tessellation).
    let sum: f64 = s.particles.iter().map(|p| p.area).sum();
    assert!((sum - s.domain_area()).abs() <= 1e-10 * s.domain_area(), "Σ A = {sum}");
    for (k, p) in s.particles.iter().enumerate() {
        assert!(p.polygon.is_convex(1e-9), "cell {k} not convex");
        assert!(checks::contains(&p.polygon, p.seed, 0.0), "cell {k} misses its seed");
        assert!(checks::contains(&p.polygon, p.centroid, 0.0), "cell {k} misses its centroid");
    }
    // Neighbour symmetry, and each beam's facet is an edge of both cells (reversed in j).
    for (i, list) in s.neighbours.iter().enumerate() {
        for &(j, b) in list {
            assert!(s.neighbours[j].contains(&(i, b)), "{i}–{j} not symmetric");
            let beam = &s.beams[b];
            assert_eq!((beam.i.min(beam.j), beam.i.max(beam.j)), (i.min(j), i.max(j)));
        }
    }
    let has_edge = |poly: &crate::dem::polygon::Polygon, a: P2, b: P2| {
        let v = &poly.vertices;
        (0..v.len()).any(|k| v[k] == a && v[(k + 1) % v.len()] == b)
    };
    for (k, b) in s.beams.iter().enumerate() {
        assert!(b.i < b.j);
        assert!(has_edge(&s.particles[b.i].polygon, b.facet[0], b.facet[1]), "beam {k} facet not in cell i");
        assert!(has_edge(&s.particles[b.j].polygon, b.facet[1], b.facet[0]), "beam {k} facet not in cell j");
        // Arms: seed = centroid + arm.
        let (pi, pj) = (&s.particles[b.i], &s.particles[b.j]);
        assert_eq!([pi.centroid[0] + b.arm_i[0], pi.centroid[1] + b.arm_i[1]], pi.seed);
        assert!((pj.centroid[0] + b.arm_j[0] - pj.seed[0]).abs() < 1e-15);
        assert!((b.area - b.facet_length * s.thickness).abs() < 1e-15);
    }
    // Euler's formula for the tessellation of a disk: V − E + F = 1, with E = beams + boundary
    // edges and Σ(cell edges) = 2·beams + boundary edges.
    let vertices: HashSet<[u64; 2]> =
        s.particles.iter().flat_map(|p| p.polygon.vertices.iter().map(|v| [v[0].to_bits(), v[1].to_bits()])).collect();
    let sum_edges: usize = s.particles.iter().map(|p| p.polygon.len()).sum();
    let boundary_edges = sum_edges - 2 * s.beams.len();
    let euler = vertices.len() as i64 - (s.beams.len() + boundary_edges) as i64 + s.particles.len() as i64;
    assert_eq!(euler, 1, "V − E + F");
}

fn max_skew(s: &Sample) -> f64 {
    s.beams.iter().map(Beam::facet_skew).fold(0.0, f64::max)
}

#[test]
fn paper_wall_counts() {
    let s = Sample::build(&paper_wall(7)).expect("the paper's wall builds");
    check_invariants(&s);
    assert_eq!(s.particles.len(), 60);
    // Particle k·6 + m is stone m of course k: the platens hold the first and last course, the
    // sides the first and last stone of each course.
    assert_eq!(s.boundary.bottom, (0..6).collect::<Vec<_>>());
    assert_eq!(s.boundary.top, (54..60).collect::<Vec<_>>());
    assert_eq!(s.boundary.left, (0..10).map(|k| 6 * k).collect::<Vec<_>>());
    assert_eq!(s.boundary.right, (0..10).map(|k| 6 * k + 5).collect::<Vec<_>>());
    // Every stone is bonded to its course neighbours: 5 per course.
    for k in 0..10 {
        for m in 0..5 {
            assert!(s.beam_between(6 * k + m, 6 * k + m + 1).is_some(), "course {k} joint {m}");
        }
    }
    // Every beam joins the same or adjacent courses.
    assert!(s.beams.iter().all(|b| b.j / 6 - b.i / 6 <= 1));
    // Mean diameter: A = 1.2/60 = 0.02 m² per stone on average, D ≈ 2 sqrt(0.02/π) = 0.16 m.
    assert!((s.mean_diameter() - 0.16).abs() < 0.01, "{}", s.mean_diameter());
    println!(
        "paper wall: {} particles, {} beams, {} merged facets, max |n·e_f| = {:e}",
        s.particles.len(),
        s.beams.len(),
        s.merged_facets.len(),
        max_skew(&s)
    );
    if s.merged_facets.is_empty() {
        assert!(max_skew(&s) < 1e-12);
    }
}

#[test]
fn regular_staggered_wall_has_the_bond_pattern() {
    // No jitter, no size variability: even courses split at m/6, odd ones offset by 1/12. Each
    // course then has 5 horizontal neighbours; with staggering every interior stone sits on two.
    let mut c = paper_wall(0);
    if let SampleLayout::Coursed(l) = &mut c.layout {
        l.jitter = 0.0;
        l.size_variability = 0.0;
    }
    let s = Sample::build(&c).expect("regular wall builds");
    check_invariants(&s);
    // 5 joints per course × 10 + (6 + 6 − 1) bonds across each of the 9 bed joints (two rows of 6
    // stones whose joints never coincide overlap in 11 pairs) = 149.
    assert_eq!((s.beams.len(), s.merged_facets.len()), (149, 0));
    for k in 0..9 {
        for m in 0..6 {
            let up = s.neighbours[6 * k + m].iter().filter(|(j, _)| j / 6 == k + 1).count();
            assert!((1..=3).contains(&up), "stone {m} of course {k} bears on {up} stones above");
        }
    }
}

#[test]
fn beams_are_perpendicular_to_their_facets() {
    // Every facet lies on its seeds' bisector: |n · e_f| at rounding level, except the facets
    // ending at a point where a tiny facet was merged (they turned when it moved).
    for cfg in [paper_wall(3), random(2000, 11)] {
        let s = Sample::build(&cfg).expect("builds");
        let moved: Vec<P2> = s.merged_facets.iter().map(|m| m.point).collect();
        let mut worst: f64 = 0.0;
        for b in s.beams.iter().filter(|b| !b.facet.iter().any(|p| moved.contains(p))) {
            worst = worst.max(b.facet_skew());
        }
        println!("{} merged facets; max |n·e_f| elsewhere {worst:e}", moved.len());
        assert!(worst < 1e-12, "max skew {worst:e}");
    }
}

#[test]
fn tiny_facets_are_merged_keeping_the_invariants() {
    // A generous tolerance (10 % of D) forces merges; the tessellation must stay valid.
    let cfg = SampleConfig { facet_tolerance: 0.1, ..random(400, 5) };
    let s = Sample::build(&cfg).expect("builds");
    check_invariants(&s);
    assert!(!s.merged_facets.is_empty());
    let tol = 0.1 * s.mean_diameter();
    assert!(s.beams.iter().all(|b| b.facet_length >= 0.9 * tol));
    for m in &s.merged_facets {
        assert!(s.beam_between(m.i, m.j).is_none());
    }
    println!("{} merged, max skew {:e}", s.merged_facets.len(), max_skew(&s));
    // Reject names the particles and the length.
    let e = Sample::build(&SampleConfig { tiny_facets: TinyFacetPolicy::Reject, ..cfg }).unwrap_err();
    assert!(matches!(e, SampleError::TinyFacet { .. }), "{e}");
    assert!(e.to_string().contains("shared by particles"), "{e}");
}

#[test]
fn same_seed_same_sample() {
    for (a, b) in [(paper_wall(9), paper_wall(10)), (random(300, 1), random(300, 2))] {
        let (s1, s2) = (Sample::build(&a).expect("builds"), Sample::build(&a).expect("builds"));
        assert_eq!(s1, s2);
        let s3 = Sample::build(&b).expect("builds");
        assert_ne!(s1.particles[0].seed, s3.particles[0].seed);
    }
}

#[test]
fn random_2000_particles() {
    let t = std::time::Instant::now();
    let s = Sample::build(&random(2000, 2024)).expect("builds");
    let dt = t.elapsed();
    check_invariants(&s);
    assert_eq!(s.particles.len(), 2000);
    let mean_neighbours = 2.0 * s.beams.len() as f64 / 2000.0;
    // Planar Voronoi: mean degree < 6, close to it in the bulk.
    assert!(mean_neighbours > 5.0 && mean_neighbours < 6.0, "{mean_neighbours}");
    println!(
        "random 2000: built in {:.1} ms, {} beams, {} merged facets, mean degree {mean_neighbours:.3}",
        dt.as_secs_f64() * 1e3,
        s.beams.len(),
        s.merged_facets.len()
    );
}

#[test]
fn set_alpha_rescales_inertia() {
    let mut s = Sample::build(&paper_wall(1)).expect("builds");
    let b = s.beams[0].clone();
    s.set_alpha(0.4).expect("valid α");
    assert!((s.beams[0].inertia - 0.5 * b.inertia).abs() <= 1e-15 * b.inertia);
    assert!((s.beams[0].inertia - beam_inertia(0.4, 1.0, b.facet_length)).abs() == 0.0);
    assert!(matches!(s.set_alpha(-1.0), Err(SampleError::InvalidConfig { field: "alpha", .. })));
}

#[test]
fn bad_input_errors() {
    let o = GeometryOptions::default();
    let e = Sample::from_seeds(1.0, 1.0, &[[0.3, 0.3], [0.3, 0.3]], &o).unwrap_err();
    assert!(matches!(e, SampleError::DuplicateSeeds { i: 0, j: 1, .. }), "{e}");
    let e = Sample::from_seeds(1.0, 1.0, &[[0.3, 0.3], [-0.1, 0.3]], &o).unwrap_err();
    assert!(matches!(e, SampleError::SeedOutsideDomain { index: 1, .. }), "{e}");
    let e = Sample::from_seeds(0.0, 1.0, &[[0.3, 0.3]], &o).unwrap_err();
    assert!(matches!(e, SampleError::InvalidConfig { field: "width", .. }), "{e}");
    let e = Sample::from_seeds(1.0, 1.0, &[], &o).unwrap_err();
    assert_eq!(e, SampleError::NoSeeds);
    let bad = GeometryOptions { thickness: 0.0, ..o };
    let e = Sample::from_seeds(1.0, 1.0, &[[0.3, 0.3]], &bad).unwrap_err();
    assert!(matches!(e, SampleError::InvalidConfig { field: "thickness", .. }), "{e}");
    let mut c = paper_wall(1);
    if let SampleLayout::Coursed(l) = &mut c.layout {
        l.height = -1.2;
    }
    assert!(matches!(Sample::build(&c), Err(SampleError::InvalidConfig { field: "height", .. })));
    // One seed: the whole domain, no beam, touching all four sides.
    let s = Sample::from_seeds(2.0, 1.0, &[[0.5, 0.5]], &o).expect("one stone");
    assert_eq!((s.particles.len(), s.beams.len()), (1, 0));
    assert!((s.particles[0].area - 2.0).abs() < 1e-15);
    assert_eq!(s.boundary.left, vec![0]);
}

#[test]
fn svg_of_the_paper_wall() {
    let s = Sample::build(&paper_wall(7)).expect("builds");
    // A made-up crack pattern: the joints of course 4 in tension (0), beams to course 5 in shear (1).
    let broken: Vec<(usize, u8)> = s
        .beams
        .iter()
        .enumerate()
        .filter_map(|(k, b)| match (b.i / 6, b.j / 6) {
            (4, 4) => Some((k, 0)),
            (4, 5) => Some((k, 1)),
            _ => None,
        })
        .collect();
    let style =
        SvgStyle {
            draw_beams: true, title: Some("Paper's wall: 10 courses × 6 stones".into()), ..SvgStyle::default()
        };
    let svg = draw_svg(&s, None, &broken, &style).expect("draws");
    assert_eq!(svg.matches("<polygon").count(), 60);
    assert!(svg.contains("tension (") && svg.contains("20 cm"));
    let _ = std::fs::write("/tmp/paper_wall.svg", &svg);
    // Deformed: the top half slides right by 2 mm, × 20.
    let u: Vec<[f64; 3]> =
        s.particles.iter().map(|p| if p.centroid[1] > 0.6 { [0.002, 0.0, 0.0] } else { [0.0; 3] }).collect();
    let style = SvgStyle { exaggeration: 20.0, ..style };
    let svg = draw_svg(&s, Some(&u), &broken, &style).expect("draws");
    let _ = std::fs::write("/tmp/paper_wall_deformed.svg", &svg);
    assert!(matches!(draw_svg(&s, Some(&u[1..]), &[], &style), Err(SampleError::DisplacementCount { got: 59, .. })));
    assert!(matches!(draw_svg(&s, None, &[(9999, 0)], &style), Err(SampleError::BeamIndex { index: 9999, .. })));
    // A random sample, for a look.
    let r = Sample::build(&random(300, 4)).expect("builds");
    let style = SvgStyle { draw_beams: true, ..SvgStyle::default() };
    let svg = draw_svg(&r, None, &[], &style).expect("draws");
    let _ = std::fs::write("/tmp/random_300.svg", &svg);
}

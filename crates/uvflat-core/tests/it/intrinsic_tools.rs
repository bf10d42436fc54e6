//! Desbrun–Meyer–Alliez 2002 §4–5 tools and the spectral conformal map, checked on real meshes
//! (`tests/data/meshes`): Lagrange point constraints (§4.1), the boundary editor and its
//! Green-function basis (§4.2).

// `!(error <= tolerance)` is deliberate: a NaN error must fail.
#![allow(clippy::neg_cmp_op_on_partial_ord)]

use uvflat_test_support::meshes;

use uvflat_core::error::Error;
use uvflat_core::methods::conformal::{default_pins, natural_conformal_map, Pin};
use uvflat_core::methods::constraints::{
    constrained_fixed_boundary_map, constrained_natural_conformal_map, pinned_natural_conformal_map, PointConstraint,
};
use uvflat_core::progress::Progress;
use uvflat_core::{fixed_boundary_map, BoundaryShape, Distribution, FixedBoundaryOptions, TriMesh, Weights};

use meshes::load;

/// A triangle none of whose vertices is on the boundary, near the middle of the triangle list.
fn interior_triangle(mesh: &TriMesh) -> u32 {
    let m = mesh.triangle_count();
    (0..m)
        .map(|k| (m / 2 + k) % m)
        .find(|&t| mesh.triangles()[t].iter().all(|&v| !mesh.is_boundary_vertex(v)))
        .expect("an interior triangle") as u32
}

fn point_of(mesh: &TriMesh, uv: &[[f64; 2]], t: u32, b: [f64; 3]) -> [f64; 2] {
    let tri = mesh.triangles()[t as usize];
    let mut p = [0.0; 2];
    for k in 0..3 {
        p[0] += b[k] * uv[tri[k] as usize][0];
        p[1] += b[k] * uv[tri[k] as usize][1];
    }
    p
}

fn max_difference(a: &[[f64; 2]], b: &[[f64; 2]]) -> f64 {
    a.iter()
        .zip(b)
        .filter(|(p, _)| p[0].is_finite())
        .map(|(p, q)| (p[0] - q[0]).abs().max((p[1] - q[1]).abs()))
        .fold(0.0, f64::max)
}

const WEIGHTS: [Weights; 4] =
    [Weights::Conformal, Weights::MeanValue, Weights::Authalic, Weights::Intrinsic { lambda: 0.5, mu: 0.5 }];

#[test]
fn a_constrained_interior_point_lands_exactly_on_its_target() {
    for file in ["disk_nefertiti_small.obj", "disk_spothead.obj"] {
        let mesh = load(file);
        for weights in WEIGHTS {
            let options = FixedBoundaryOptions { weights, ..Default::default() };
            let free = fixed_boundary_map(&mesh, &options).expect("unconstrained map");
            let t = interior_triangle(&mesh);
            let b = [0.2, 0.3, 0.5];
            let start = point_of(&mesh, &free, t, b);
            let target = [start[0] + 0.02, start[1] - 0.01];
            let c = [PointConstraint { triangle: t, barycentric: b, uv: target }];
            let uv =
                constrained_fixed_boundary_map(&mesh, &options, &c, &mut Progress::none()).expect("constrained map");
            let got = point_of(&mesh, &uv, t, b);
            let error = (got[0] - target[0]).abs().max((got[1] - target[1]).abs());
            assert!(error <= 1e-9, "{file} {weights:?}: constrained point is {error:e} from its target");
            // The boundary stays where the options put it.
            for &v in mesh.boundary_loops().iter().flatten() {
                assert_eq!(uv[v as usize], free[v as usize], "{file}: boundary vertex {v} moved");
            }
            assert!(max_difference(&uv, &free) > 1e-3, "{file} {weights:?}: the constraint changed nothing");
        }
    }
}

#[test]
fn an_already_satisfied_constraint_leaves_the_map_unchanged() {
    for file in ["disk_nefertiti_small.obj", "disk_spothead.obj"] {
        let mesh = load(file);
        for weights in WEIGHTS {
            let options =
                FixedBoundaryOptions { weights, shape: BoundaryShape::Square, distribution: Distribution::Uniform };
            let free = fixed_boundary_map(&mesh, &options).expect("unconstrained map");
            let t = interior_triangle(&mesh);
            let b = [0.6, 0.1, 0.3];
            let c = [PointConstraint { triangle: t, barycentric: b, uv: point_of(&mesh, &free, t, b) }];
            let uv =
                constrained_fixed_boundary_map(&mesh, &options, &c, &mut Progress::none()).expect("constrained map");
            let d = max_difference(&uv, &free);
            assert!(d <= 1e-9, "{file} {weights:?}: satisfied constraint moved the map by {d:e}");
        }
    }
}

#[test]
fn conflicting_constraints_are_reported_and_redundant_ones_accepted() {
    let mesh = load("disk_nefertiti_small.obj");
    let options = FixedBoundaryOptions { weights: Weights::Conformal, ..Default::default() };
    let t = interior_triangle(&mesh);
    let b = [0.2, 0.3, 0.5];
    let one = PointConstraint { triangle: t, barycentric: b, uv: [0.5, 0.5] };
    let same = PointConstraint { barycentric: [0.4, 0.6, 1.0], ..one }; // same point, scaled coordinates
    let other = PointConstraint { uv: [0.6, 0.5], ..one };
    let uv = constrained_fixed_boundary_map(&mesh, &options, &[one, same], &mut Progress::none())
        .expect("redundant constraints");
    let got = point_of(&mesh, &uv, t, b);
    assert!((got[0] - 0.5).abs() < 1e-9 && (got[1] - 0.5).abs() < 1e-9);
    match constrained_fixed_boundary_map(&mesh, &options, &[one, other], &mut Progress::none()) {
        Err(Error::InvalidArgument(text)) => assert!(text.contains("constraint 1 conflicts"), "{text}"),
        other => panic!("conflict not reported: {other:?}"),
    }
    // A point of a triangle whose three vertices are on the (fixed) boundary cannot move.
    let boundary_triangle = (0..mesh.triangle_count())
        .find(|&t| mesh.triangles()[t].iter().all(|&v| mesh.is_boundary_vertex(v)))
        .map(|t| t as u32);
    if let Some(bt) = boundary_triangle {
        let c = PointConstraint { triangle: bt, barycentric: [1.0, 1.0, 1.0], uv: [9.0, 9.0] };
        assert!(matches!(
            constrained_fixed_boundary_map(&mesh, &options, &[c], &mut Progress::none()),
            Err(Error::InvalidArgument(_))
        ));
    }
    // Bad input: triangle out of range, zero-sum barycentric coordinates, NaN target.
    for bad in [
        PointConstraint { triangle: mesh.triangle_count() as u32, ..one },
        PointConstraint { barycentric: [1.0, -1.0, 0.0], ..one },
        PointConstraint { uv: [f64::NAN, 0.0], ..one },
    ] {
        assert!(matches!(
            constrained_fixed_boundary_map(&mesh, &options, &[bad], &mut Progress::none()),
            Err(Error::InvalidArgument(_))
        ));
    }
}

#[test]
fn two_pins_as_constraints_give_the_two_pin_natural_conformal_map() {
    for file in ["disk_nefertiti_small.obj", "disk_spothead.obj", "holes_annulus.obj"] {
        let mesh = load(file);
        let pins = default_pins(&mesh);
        let reference = natural_conformal_map(&mesh, Some(pins)).expect("natural conformal");
        let uv = pinned_natural_conformal_map(&mesh, &pins, &mut Progress::none()).expect("pinned");
        let scale = pins[1].1[0];
        let d = max_difference(&uv, &reference);
        assert!(d <= 1e-9 * scale, "{file}: constrained 2-pin map differs by {d:e}");
    }
}

#[test]
fn more_than_two_pins_are_honoured_and_satisfied_ones_change_nothing() {
    let mesh = load("disk_spothead.obj");
    let pins = default_pins(&mesh);
    let reference = natural_conformal_map(&mesh, Some(pins)).expect("natural conformal");
    // A third pin where the map already puts the vertex: same map.
    let t = interior_triangle(&mesh);
    let v = mesh.triangles()[t as usize][0];
    let three: Vec<Pin> = vec![pins[0], pins[1], (v, reference[v as usize])];
    let uv = pinned_natural_conformal_map(&mesh, &three, &mut Progress::none()).expect("3 pins");
    let scale = pins[1].1[0];
    assert!(max_difference(&uv, &reference) <= 1e-9 * scale);
    // Four pins elsewhere: each lands exactly.
    let w = mesh.triangles()[t as usize][1];
    let four: Vec<Pin> = vec![pins[0], pins[1], (v, [0.3 * scale, 0.2 * scale]), (w, [0.35 * scale, 0.1 * scale])];
    let uv = pinned_natural_conformal_map(&mesh, &four, &mut Progress::none()).expect("4 pins");
    for (p, target) in &four {
        let got = uv[*p as usize];
        assert!(
            (got[0] - target[0]).abs().max((got[1] - target[1]).abs()) <= 1e-9 * scale,
            "pin {p}: {got:?} vs {target:?}"
        );
    }
    // An interior point constraint together with two pins.
    let b = [0.25, 0.25, 0.5];
    let target = [0.4 * scale, 0.15 * scale];
    let mut c: Vec<PointConstraint> = pins
        .iter()
        .map(|&(v, uv)| uvflat_core::methods::constraints::vertex_constraint(&mesh, v, uv).expect("pin"))
        .collect();
    c.push(PointConstraint { triangle: t, barycentric: b, uv: target });
    let uv = constrained_natural_conformal_map(&mesh, &c, &mut Progress::none()).expect("constrained");
    let got = point_of(&mesh, &uv, t, b);
    assert!((got[0] - target[0]).abs().max((got[1] - target[1]).abs()) <= 1e-9 * scale);
    // Too few or collapsing constraints are refused.
    assert!(matches!(
        pinned_natural_conformal_map(&mesh, &pins[..1], &mut Progress::none()),
        Err(Error::InvalidArgument(_))
    ));
    let same: Vec<Pin> = vec![(pins[0].0, [1.0, 1.0]), (pins[1].0, [1.0, 1.0])];
    assert!(matches!(
        pinned_natural_conformal_map(&mesh, &same, &mut Progress::none()),
        Err(Error::InvalidArgument(_))
    ));
    let conflicting: Vec<Pin> = vec![pins[0], pins[1], (pins[1].0, [0.0, 5.0])];
    assert!(matches!(
        pinned_natural_conformal_map(&mesh, &conflicting, &mut Progress::none()),
        Err(Error::InvalidArgument(_))
    ));
}

// ---------------------------------------------------------------------------------------------
// Boundary editor (§4.2)

use uvflat_core::methods::intrinsic::BoundaryEditor;

/// The boundary loop of the editor moved to a wobbly star: a non-trivial boundary.
fn star_boundary(editor: &BoundaryEditor, phase: f64) -> Vec<[f64; 2]> {
    let b = editor.boundary_vertices().len() as f64;
    (0..editor.boundary_vertices().len())
        .map(|i| {
            let a = std::f64::consts::TAU * i as f64 / b;
            let r = 1.0 + 0.2 * (5.0 * a + phase).cos();
            [r * a.cos(), r * a.sin()]
        })
        .collect()
}

#[test]
fn editor_solve_equals_a_fresh_fixed_boundary_solve_and_the_green_basis_sum() {
    for (file, lambda, mu) in [
        ("disk_nefertiti_small.obj", 1.0, 0.0),
        ("disk_nefertiti_small.obj", 0.3, 0.7),
        ("holes_annulus.obj", 0.5, 0.5),
    ] {
        let mesh = load(file);
        let editor = BoundaryEditor::new(&mesh, lambda, mu, &mut Progress::none()).expect("editor");
        let basis = editor.green_basis(1 << 30, &mut Progress::none()).expect("basis");
        for phase in [0.0, 1.0] {
            let boundary = star_boundary(&editor, phase);
            let uv = editor.solve(&boundary).expect("editor solve");
            let given: Vec<(u32, [f64; 2])> =
                editor.boundary_vertices().iter().copied().zip(boundary.iter().copied()).collect();
            let options = FixedBoundaryOptions {
                weights: Weights::Intrinsic { lambda, mu },
                shape: BoundaryShape::Given(given),
                distribution: Distribution::Uniform,
            };
            let fresh = fixed_boundary_map(&mesh, &options).expect("fresh solve");
            let d = max_difference(&uv, &fresh);
            assert!(d <= 1e-9, "{file} λ={lambda} μ={mu}: editor vs fresh solve differ by {d:e}");
            let summed = basis.evaluate(&boundary);
            let d = max_difference(&summed, &fresh);
            assert!(d <= 1e-9, "{file} λ={lambda} μ={mu}: Green basis sum vs fresh solve differ by {d:e}");
        }
        // Memory cap and bad input.
        let bytes = editor.green_basis_bytes().expect("size");
        assert!(matches!(editor.green_basis(bytes - 1, &mut Progress::none()), Err(Error::InvalidArgument(_))));
        assert!(matches!(editor.solve(&[[0.0, 0.0]]), Err(Error::InvalidArgument(_))));
    }
}

#[test]
fn concurrent_editor_solves_agree_with_sequential_ones() {
    let mesh = load("disk_spothead.obj");
    let editor = BoundaryEditor::new(&mesh, 1.0, 0.0, &mut Progress::none()).expect("editor");
    let expected: Vec<Vec<[f64; 2]>> =
        (0..4).map(|k| editor.solve(&star_boundary(&editor, k as f64)).expect("solve")).collect();
    std::thread::scope(|s| {
        let handles: Vec<_> = (0..4)
            .map(|k| {
                let editor = &editor;
                s.spawn(move || editor.solve(&star_boundary(editor, k as f64)).expect("solve"))
            })
            .collect();
        for (k, h) in handles.into_iter().enumerate() {
            let d = max_difference(&h.join().expect("thread"), &expected[k]);
            assert!(d <= 1e-12, "concurrent solve {k} differs by {d:e}");
        }
    });
}

//! Bad input: every error names what was wrong, and a failed call changes nothing.

use dvh::fixtures::icosphere;
use dvh::{BuildOptions, Error, Mesh, Pairs, Pose, QueryOptions, Side, collide};

fn sphere() -> Mesh {
    let m = icosphere(2);
    Mesh::new(&m.positions, &m.triangles, &BuildOptions::default()).unwrap()
}

#[test]
fn build_errors_name_the_culprit() {
    let p = [0.0, 0.0, 0.0, 1.0, 0.0, 0.0, 0.0, 1.0, 0.0];
    let o = BuildOptions::default();
    assert_eq!(Mesh::new(&p, &[], &o).unwrap_err(), Error::NoTriangles);
    assert_eq!(
        Mesh::new(&p[..8], &[0, 1, 2], &o).unwrap_err(),
        Error::PositionsLength { len: 8 }
    );
    assert_eq!(
        Mesh::new(&p, &[0, 1, 2, 0], &o).unwrap_err(),
        Error::TrianglesLength { len: 4 }
    );
    let e = Mesh::new(&p, &[0, 1, 2, 2, 1, 9], &o).unwrap_err();
    assert_eq!(
        e,
        Error::IndexOutOfRange {
            triangle: 1,
            corner: 2,
            index: 9,
            vertex_count: 3
        }
    );
    assert_eq!(
        e.to_string(),
        "triangle 1, corner 2: vertex index 9 is out of range (the mesh has 3 vertices)"
    );
    let mut q = p;
    q[7] = f64::NAN;
    let e = Mesh::new(&q, &[0, 1, 2], &o).unwrap_err();
    assert!(
        matches!(e, Error::NonFiniteCoordinate { vertex: 2, axis: 1, value } if value.is_nan())
    );
    assert_eq!(
        e.to_string(),
        "vertex 2: coordinate y is NaN, not a finite number"
    );
    q[7] = f64::NEG_INFINITY;
    assert!(
        Mesh::new(&q, &[0, 1, 2], &o)
            .unwrap_err()
            .to_string()
            .contains("-inf")
    );
}

#[test]
fn a_failed_refit_leaves_the_mesh_exactly_as_it_was() {
    let mut mesh = sphere();
    let other = sphere();
    let before = format!("{mesh:?}");
    let mut pairs = Pairs::new();
    collide(
        &mesh,
        None,
        &other,
        None,
        &QueryOptions::default(),
        &mut pairs,
    )
    .unwrap();
    let pairs_before = pairs.as_slice().to_vec();

    let n = mesh.vertex_count() * 3;
    let mut p: Vec<f64> = mesh
        .positions()
        .as_flattened()
        .iter()
        .map(|x| x * 2.0)
        .collect();
    p[n - 1] = f64::INFINITY;
    let e = mesh.refit(&p).unwrap_err();
    assert_eq!(
        e,
        Error::NonFiniteCoordinate {
            vertex: mesh.vertex_count() - 1,
            axis: 2,
            value: f64::INFINITY
        }
    );
    assert_eq!(
        mesh.refit(&p[..n - 3]).unwrap_err(),
        Error::VertexCountMismatch {
            expected: n / 3,
            got: n / 3 - 1
        }
    );
    assert_eq!(
        mesh.refit(&p[..n - 1]).unwrap_err(),
        Error::PositionsLength { len: n - 1 }
    );
    assert_eq!(
        format!("{mesh:?}"),
        before,
        "a failed refit changed the mesh"
    );
    mesh.validate().unwrap();
    collide(
        &mesh,
        None,
        &other,
        None,
        &QueryOptions::default(),
        &mut pairs,
    )
    .unwrap();
    assert_eq!(pairs.as_slice(), &pairs_before[..]);
}

#[test]
fn a_failed_query_leaves_the_result_buffer_as_it_was() {
    let a = sphere();
    let b = sphere();
    let mut pairs = Pairs::new();
    collide(&a, None, &b, None, &QueryOptions::default(), &mut pairs).unwrap();
    let before = pairs.as_slice().to_vec();
    assert!(!before.is_empty());

    let m = icosphere(1);
    let huge: Vec<f64> = m.positions.iter().map(|x| x * 1e299 + 5e299).collect();
    let far = Mesh::new(&huge, &m.triangles, &BuildOptions::default()).unwrap();
    let pose = Pose::new(Pose::IDENTITY.rotation(), [1e300, 0.0, 0.0]).unwrap();
    let e = collide(
        &a,
        None,
        &far,
        Some(&pose),
        &QueryOptions::default(),
        &mut pairs,
    )
    .unwrap_err();
    assert!(
        matches!(e, Error::PoseOutOfRange { side: Side::B, .. }),
        "{e}"
    );
    let e = collide(
        &far,
        Some(&pose),
        &a,
        None,
        &QueryOptions::default(),
        &mut pairs,
    )
    .unwrap_err();
    assert!(
        matches!(e, Error::PoseOutOfRange { side: Side::A, .. }),
        "{e}"
    );
    assert!(e.to_string().contains("pose of mesh A"), "{e}");
    assert_eq!(pairs.as_slice(), &before[..]);
    // The same mesh without a pose is fine: huge coordinates are valid input.
    collide(&a, None, &far, None, &QueryOptions::default(), &mut pairs).unwrap();
    assert!(pairs.is_empty());
}

#[test]
fn non_rigid_poses_are_refused() {
    let shear = [[1.0, 0.1, 0.0], [0.0, 1.0, 0.0], [0.0, 0.0, 1.0]];
    let e = Pose::new(shear, [0.0; 3]).unwrap_err();
    assert!(matches!(e, Error::NonRigidPose { deviation, .. } if deviation > 0.09));
    assert!(
        e.to_string().starts_with("pose rotation is not a rotation"),
        "{e}"
    );
}

#[test]
fn other_layouts_give_the_same_mesh() {
    use dvh::fixtures::torus;
    let t = torus(0.5, 0.2, 12, 8);
    // Interleaved f32 position + normal, as engines keep vertices.
    let interleaved: Vec<f32> = t
        .positions
        .chunks(3)
        .flat_map(|p| [p[0] as f32, p[1] as f32, p[2] as f32, 0.0, 0.0, 1.0])
        .collect();
    let read = |i: usize| [0, 1, 2].map(|k| f64::from(interleaved[i * 6 + k]));
    let flat: Vec<f64> = (0..t.vertex_count()).flat_map(read).collect();
    let a = Mesh::new(&flat, &t.triangles, &BuildOptions::default()).unwrap();
    let mut b = Mesh::new_with(
        t.vertex_count(),
        read,
        &t.triangles,
        &BuildOptions::default(),
    )
    .unwrap();
    assert_eq!(format!("{a:?}"), format!("{b:?}"));
    let before = format!("{b:?}");
    let e = b
        .refit_with(t.vertex_count(), |i| {
            if i == 5 {
                [0.0, f64::NAN, 0.0]
            } else {
                read(i)
            }
        })
        .unwrap_err();
    assert!(matches!(
        e,
        Error::NonFiniteCoordinate {
            vertex: 5,
            axis: 1,
            ..
        }
    ));
    assert_eq!(
        b.refit_with(3, read).unwrap_err(),
        Error::VertexCountMismatch {
            expected: t.vertex_count(),
            got: 3
        }
    );
    assert_eq!(format!("{b:?}"), before);
    let mut c = a.clone();
    c.refit(&flat.iter().map(|x| x * 0.5).collect::<Vec<_>>())
        .unwrap();
    b.refit_with(t.vertex_count(), |i| read(i).map(|x| x * 0.5))
        .unwrap();
    assert_eq!(format!("{b:?}"), format!("{c:?}"));
    b.validate().unwrap();
}

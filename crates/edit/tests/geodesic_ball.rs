//! The geodesic ball (`edit::bendels_klein::geodesic_ball`) on the unit sphere, where the
//! surface distance is the great-circle distance, against the kernel's edge-path ball.

use edit::bendels_klein::geodesic_ball;
use edit::bendels_klein::sphere_distance;
use edit::bendels_klein::BendelsKleinError;
use glam::DVec3;
use halfedge::generators;

#[test]
fn the_geodesic_ball_on_a_sphere_is_the_spherical_cap() {
    let sphere = generators::icosphere(5);
    let edge = sphere.mean_edge_length();
    let top = sphere.extreme_vertex(DVec3::Z).unwrap().unwrap();
    let c = sphere.position(top);
    for radius in [0.3, 0.8, 1.5] {
        let (ball, distance) = geodesic_ball(&sphere, &[top], radius).unwrap();
        assert!(ball.contains(&sphere, top));
        for v in sphere.vertices() {
            let exact = sphere_distance(c, sphere.position(v));
            let d = distance[sphere.vertex_index(v)];
            if exact < radius - 2.0 * edge {
                assert!(
                    ball.contains(&sphere, v),
                    "{v} at {exact} left out of {radius}"
                );
                assert!((d - exact).abs() < 0.02 * exact.max(edge), "{d} vs {exact}");
            }
            if exact > radius + 2.0 * edge {
                assert!(
                    !ball.contains(&sphere, v),
                    "{v} at {exact} in a ball of {radius}"
                );
                assert!(d.is_infinite());
            }
        }
        // Edge paths are longer than surface paths: the edge ball is inside, and
        // noticeably smaller.
        let edges = sphere.select_edge_ball(&[top], radius).unwrap();
        for v in edges.vertices(&sphere) {
            assert!(ball.contains(&sphere, v));
        }
        assert!(edges.len() < ball.len());
    }
}

#[test]
fn several_seeds_and_bad_arguments() {
    let sphere = generators::icosphere(3);
    let top = sphere.extreme_vertex(DVec3::Z).unwrap().unwrap();
    let bottom = sphere.extreme_vertex(-DVec3::Z).unwrap().unwrap();
    let (both, _) = geodesic_ball(&sphere, &[top, bottom], 0.5).unwrap();
    let (one, _) = geodesic_ball(&sphere, &[top], 0.5).unwrap();
    let (other, _) = geodesic_ball(&sphere, &[bottom], 0.5).unwrap();
    assert_eq!(both.len(), one.len() + other.len());
    let (point, _) = geodesic_ball(&sphere, &[top], 0.0).unwrap();
    assert_eq!(point.vertices(&sphere), vec![top]);
    assert!(matches!(
        geodesic_ball(&sphere, &[top], -1.0),
        Err(BendelsKleinError::InvalidParameter { .. })
    ));
    assert!(matches!(
        geodesic_ball(&sphere, &[top], f64::NAN),
        Err(BendelsKleinError::InvalidParameter { .. })
    ));
    let mut collapsed = sphere.clone();
    let e = collapsed.halfedges().next().unwrap();
    let gone = collapsed.from_vertex(e);
    collapsed.collapse(e).unwrap();
    assert!(matches!(
        geodesic_ball(&collapsed, &[gone], 0.5),
        Err(BendelsKleinError::Mesh(halfedge::Error::InvalidHandle(_)))
    ));
}

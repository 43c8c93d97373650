//! A procedural robot: boxes, capped cylinders and small UV spheres.
//!
//! Parts are built in their own frame and placed by a [`Frame`] (rotation and
//! translation); arms and legs are kinematic chains of frames, so a pose is a
//! few angles.

use std::f64::consts::PI;

use super::sphere::sphere;
use super::vector::{add, fit_unit_box, scale};
use crate::scene::desc::MeshData;

/// Segments around each cylinder.
const CYLINDER_SEGMENTS: u32 = 16;

/// A robot of 14 boxes, 8 cylinders and 5 spheres (1488 triangles), standing on
/// its feet along +y, facing +z. Its left arm (+x side) is raised sideways and bent
/// at the elbow, its right arm swings forward, its left leg steps forward and its
/// head turns a little towards its raised arm, so it reads as a figure from a
/// three-quarter view.
///
/// Box faces and cylinder caps have their own vertices with face normals, so their
/// edges stay sharp; cylinder walls and spheres are smooth. Parts interpenetrate
/// where they join. Like the teapot, the whole figure is centred and scaled so that
/// its bounding box is centred at the origin with largest half-extent 1 (the
/// height).
pub fn robot() -> MeshData {
    let mut robot = MeshData::default();
    let root = Frame::IDENTITY;

    // Body, from the floor (y = 0) up; lengths in robot units, about 3 tall.
    let pelvis = root.moved([0.0, 1.4, 0.0]);
    add_part(&mut robot, &cuboid([0.3, 0.1, 0.16]), pelvis);
    let chest = pelvis.moved([0.0, 0.55, 0.0]);
    add_part(&mut robot, &cuboid([0.42, 0.45, 0.24]), chest);
    add_part(
        &mut robot,
        &cuboid([0.2, 0.12, 0.03]),
        chest.moved([0.0, 0.1, 0.25]),
    );
    let neck = chest.moved([0.0, 0.5, 0.0]);
    add_part(&mut robot, &cylinder(0.1, 0.08, CYLINDER_SEGMENTS), neck);
    let head = neck.moved([0.0, 0.28, 0.0]).turned(Axis::Y, 15.0);
    add_part(&mut robot, &cuboid([0.25, 0.2, 0.22]), head);
    for x in [-0.1, 0.1] {
        add_part(&mut robot, &ball(0.055), head.moved([x, 0.04, 0.21]));
    }
    add_part(
        &mut robot,
        &cylinder(0.02, 0.1, 8),
        head.moved([0.0, 0.3, 0.0]),
    );
    add_part(&mut robot, &ball(0.05), head.moved([0.0, 0.42, 0.0]));

    // Arms hang from the shoulders; `side` is +1 for the robot's left (+x).
    let arm = |robot: &mut MeshData, side: f64, pose: ArmPose| {
        let joint = chest.moved([side * 0.49, 0.3, 0.0]);
        add_part(
            robot,
            &cylinder(0.12, 0.07, CYLINDER_SEGMENTS),
            joint.turned(Axis::Z, 90.0),
        );
        let shoulder = joint
            .moved([side * 0.07, 0.0, 0.0])
            .turned(Axis::Z, side * pose.raise)
            .turned(Axis::X, -pose.swing);
        add_part(
            robot,
            &cuboid([0.08, 0.25, 0.08]),
            shoulder.moved([0.0, -0.25, 0.0]),
        );
        let elbow = shoulder.moved([0.0, -0.52, 0.0]);
        add_part(
            robot,
            &cylinder(0.085, 0.085, CYLINDER_SEGMENTS),
            elbow.turned(Axis::Z, 90.0),
        );
        let forearm = elbow
            .turned(Axis::Z, side * pose.elbow_raise)
            .turned(Axis::X, -pose.elbow_swing);
        add_part(
            robot,
            &cuboid([0.07, 0.22, 0.07]),
            forearm.moved([0.0, -0.24, 0.0]),
        );
        add_part(robot, &ball(0.11), forearm.moved([0.0, -0.5, 0.0]));
    };
    let raised = ArmPose {
        raise: 75.0,
        swing: 10.0,
        elbow_raise: 45.0,
        elbow_swing: 0.0,
    };
    let hanging = ArmPose {
        raise: 8.0,
        swing: 15.0,
        elbow_raise: 0.0,
        elbow_swing: 30.0,
    };
    arm(&mut robot, 1.0, raised);
    arm(&mut robot, -1.0, hanging);

    // Legs hang from the hips; `stride` swings a leg forward in degrees.
    let leg = |robot: &mut MeshData, side: f64, stride: f64| {
        let hip = pelvis
            .moved([side * 0.18, -0.05, 0.0])
            .turned(Axis::X, -stride);
        add_part(
            robot,
            &cuboid([0.13, 0.3, 0.14]),
            hip.moved([0.0, -0.3, 0.0]),
        );
        let knee = hip.moved([0.0, -0.62, 0.0]);
        add_part(
            robot,
            &cylinder(0.1, 0.12, CYLINDER_SEGMENTS),
            knee.turned(Axis::Z, 90.0),
        );
        let shin = knee.turned(Axis::X, stride);
        add_part(
            robot,
            &cuboid([0.11, 0.3, 0.12]),
            shin.moved([0.0, -0.32, 0.0]),
        );
        add_part(
            robot,
            &cuboid([0.13, 0.05, 0.2]),
            shin.moved([0.0, -0.63, 0.06]),
        );
    };
    leg(&mut robot, 1.0, 12.0);
    leg(&mut robot, -1.0, -4.0);

    fit_unit_box(&mut robot.positions);
    robot
}

/// Angles of an arm in degrees: `raise` turns it sideways away from the body,
/// `swing` forward; the `elbow_` angles bend the forearm the same ways.
#[derive(Clone, Copy)]
struct ArmPose {
    raise: f64,
    swing: f64,
    elbow_raise: f64,
    elbow_swing: f64,
}

/// Appends `part`, placed by `frame`, to `mesh`.
fn add_part(mesh: &mut MeshData, part: &MeshData, frame: Frame) {
    let base = mesh.positions.len() as u32;
    mesh.positions
        .extend(part.positions.iter().map(|&p| frame.point(p)));
    mesh.normals
        .extend(part.normals.iter().map(|&n| frame.vector(n)));
    mesh.triangles
        .extend(part.triangles.iter().map(|t| t.map(|i| base + i)));
}

/// A box centred at the origin with the given half-extents: 6 faces of 4 vertices
/// each, with face normals.
fn cuboid(half: [f64; 3]) -> MeshData {
    let mut mesh = MeshData::default();
    for k in 0..3 {
        let axis = unit(k);
        for sign in [1.0, -1.0] {
            // (u, v, normal) right-handed, so the corners below run
            // counter-clockwise seen from outside.
            let normal = scale(axis, sign);
            let (u, v) = if sign > 0.0 {
                (unit((k + 1) % 3), unit((k + 2) % 3))
            } else {
                (unit((k + 2) % 3), unit((k + 1) % 3))
            };
            let base = mesh.positions.len() as u32;
            for (su, sv) in [(-1.0, -1.0), (1.0, -1.0), (1.0, 1.0), (-1.0, 1.0)] {
                let corner = add(normal, add(scale(u, su), scale(v, sv)));
                mesh.positions
                    .push(std::array::from_fn(|i| corner[i] * half[i]));
                mesh.normals.push(normal);
            }
            mesh.triangles
                .extend([[base, base + 1, base + 2], [base, base + 2, base + 3]]);
        }
    }
    mesh
}

/// A capped cylinder along y, centred at the origin. The wall has one ring of
/// vertices at each end with radial (smooth) normals; each cap is a fan with its
/// own vertices and the cap's face normal.
fn cylinder(radius: f64, half_height: f64, segments: u32) -> MeshData {
    let around: Vec<[f64; 3]> = (0..segments)
        .map(|j| {
            let (s, c) = (2.0 * PI * f64::from(j) / f64::from(segments)).sin_cos();
            [s, 0.0, c]
        })
        .collect();
    let ring = |y: f64| {
        around
            .iter()
            .map(move |d| add(scale(*d, radius), [0.0, y, 0.0]))
    };
    let next = |j: u32| (j + 1) % segments;

    let mut mesh = MeshData::default();
    // Wall: bottom ring 0..n, top ring n..2n.
    mesh.positions
        .extend(ring(-half_height).chain(ring(half_height)));
    mesh.normals.extend(around.iter().chain(&around));
    for j in 0..segments {
        let (b0, b1) = (j, next(j));
        let (t0, t1) = (segments + j, segments + next(j));
        mesh.triangles.extend([[b0, b1, t1], [b0, t1, t0]]);
    }
    // Caps: centre, then the ring.
    for (y, normal) in [
        (half_height, [0.0, 1.0, 0.0]),
        (-half_height, [0.0, -1.0, 0.0]),
    ] {
        let centre = mesh.positions.len() as u32;
        mesh.positions.push([0.0, y, 0.0]);
        mesh.positions.extend(ring(y));
        mesh.normals
            .extend(std::iter::repeat_n(normal, segments as usize + 1));
        for j in 0..segments {
            let (r0, r1) = (centre + 1 + j, centre + 1 + next(j));
            mesh.triangles.push(if y > 0.0 {
                [centre, r0, r1]
            } else {
                [centre, r1, r0]
            });
        }
    }
    mesh
}

/// A 12 x 8 UV sphere of the given radius centred at the origin.
fn ball(radius: f64) -> MeshData {
    let mut mesh = sphere(12, 8);
    for p in &mut mesh.positions {
        *p = scale(*p, radius);
    }
    mesh
}

/// The unit vector along axis `k`.
fn unit(k: usize) -> [f64; 3] {
    std::array::from_fn(|i| if i == k { 1.0 } else { 0.0 })
}

/// A coordinate axis to turn about.
#[derive(Clone, Copy)]
enum Axis {
    X = 0,
    Y = 1,
    Z = 2,
}

/// A rigid placement: `point(p) = rotation * p + origin`. [`Frame::moved`] and
/// [`Frame::turned`] act in the frame's own (local) axes, so chaining them walks
/// down a limb.
#[derive(Clone, Copy)]
struct Frame {
    /// Columns are the frame's x, y and z axes in world space.
    axes: [[f64; 3]; 3],
    origin: [f64; 3],
}

impl Frame {
    const IDENTITY: Frame = Frame {
        axes: [[1.0, 0.0, 0.0], [0.0, 1.0, 0.0], [0.0, 0.0, 1.0]],
        origin: [0.0; 3],
    };

    /// The same frame moved by `offset` along its own axes.
    fn moved(self, offset: [f64; 3]) -> Frame {
        Frame {
            origin: self.point(offset),
            ..self
        }
    }

    /// The same frame turned by `degrees` (right-handed) about its own `axis`.
    fn turned(self, axis: Axis, degrees: f64) -> Frame {
        let (s, c) = degrees.to_radians().sin_cos();
        let k = axis as usize;
        let (i, j) = ((k + 1) % 3, (k + 2) % 3);
        // Rotating about axis k turns axis i towards axis j.
        let (ai, aj) = (self.axes[i], self.axes[j]);
        let mut axes = self.axes;
        axes[i] = add(scale(ai, c), scale(aj, s));
        axes[j] = add(scale(aj, c), scale(ai, -s));
        Frame { axes, ..self }
    }

    /// A point given in this frame, in world space.
    fn point(&self, p: [f64; 3]) -> [f64; 3] {
        add(self.vector(p), self.origin)
    }

    /// A direction given in this frame, in world space.
    fn vector(&self, v: [f64; 3]) -> [f64; 3] {
        (0..3).fold([0.0; 3], |sum, k| add(sum, scale(self.axes[k], v[k])))
    }
}

#[cfg(test)]
mod tests {
    use std::collections::HashMap;

    use super::*;
    use crate::scene::mesh::tests::{assert_well_formed, edge_stats, signed_volume};
    use crate::scene::mesh::vector::{cross, dot, face_normal, normalize};

    /// Triangles with vertices identified by position rather than index, so that a
    /// part's flat faces join up again.
    fn by_position(mesh: &MeshData) -> Vec<[u32; 3]> {
        let mut ids: HashMap<[u64; 3], u32> = HashMap::new();
        let mut id_of = |p: [f64; 3]| {
            let n = ids.len() as u32;
            *ids.entry(p.map(f64::to_bits)).or_insert(n)
        };
        let ids: Vec<u32> = mesh.positions.iter().map(|&p| id_of(p)).collect();
        mesh.triangles
            .iter()
            .map(|t| t.map(|i| ids[i as usize]))
            .collect()
    }

    fn assert_closed_and_outward(part: &MeshData) {
        assert_well_formed(part);
        let stats = edge_stats(&by_position(part));
        assert_eq!((stats.boundary, stats.bad), (0, 0), "{stats:?}");
        assert!(signed_volume(part) > 0.0);
    }

    #[test]
    fn parts_are_closed_and_face_outward() {
        let b = cuboid([1.0, 2.0, 3.0]);
        assert_closed_and_outward(&b);
        assert!((signed_volume(&b) - 48.0).abs() < 1e-12);
        let c = cylinder(0.5, 1.0, 16);
        assert_closed_and_outward(&c);
        assert_eq!(c.triangles.len(), 64);
        assert_closed_and_outward(&ball(0.3));
    }

    #[test]
    fn flat_faces_have_face_normals() {
        for part in [cuboid([1.0, 2.0, 3.0]), cylinder(0.5, 1.0, 16)] {
            for t in &part.triangles {
                let n = normalize(face_normal(&part.positions, t)).unwrap();
                let flat = t
                    .iter()
                    .all(|&i| (dot(part.normals[i as usize], n) - 1.0).abs() < 1e-12);
                // Every box face is flat; cylinder caps are flat, wall normals are radial.
                let wall = t.iter().all(|&i| part.normals[i as usize][1] == 0.0);
                assert!(flat || wall, "{t:?}");
            }
        }
    }

    #[test]
    fn frames_turn_right_handed_and_move_along_their_own_axes() {
        let f = Frame::IDENTITY.turned(Axis::Z, 90.0);
        assert_close(f.vector([1.0, 0.0, 0.0]), [0.0, 1.0, 0.0]);
        assert_close(f.vector([0.0, 1.0, 0.0]), [-1.0, 0.0, 0.0]);
        assert_close(f.moved([2.0, 0.0, 0.0]).origin, [0.0, 2.0, 0.0]);
        let g = Frame::IDENTITY.turned(Axis::X, 90.0);
        assert_close(g.vector([0.0, 1.0, 0.0]), [0.0, 0.0, 1.0]);
        let h = Frame::IDENTITY.turned(Axis::Y, 90.0);
        assert_close(h.vector([0.0, 0.0, 1.0]), [1.0, 0.0, 0.0]);
        // A chain stays a rotation.
        let chain = f
            .turned(Axis::X, 30.0)
            .moved([0.0, 1.0, 0.0])
            .turned(Axis::Y, -70.0);
        let [x, y, z] = chain.axes;
        assert_close(cross(x, y), z);
        assert!((dot(x, x) - 1.0).abs() < 1e-12);
    }

    fn assert_close(a: [f64; 3], b: [f64; 3]) {
        assert!(
            (0..3).all(|k| (a[k] - b[k]).abs() < 1e-12),
            "{a:?} != {b:?}"
        );
    }

    #[test]
    fn robot_is_a_posed_figure_in_the_unit_box() {
        let m = robot();
        assert_well_formed(&m);
        assert_eq!(m.triangles.len(), 1488);
        let stats = edge_stats(&by_position(&m));
        assert_eq!((stats.boundary, stats.bad), (0, 0), "{stats:?}");
        assert!(signed_volume(&m) > 0.0);
        let (lo, hi) = bounds(&m.positions);
        for k in 0..3 {
            assert!((lo[k] + hi[k]).abs() < 1e-12, "centred on axis {k}");
        }
        assert!((hi[1] - 1.0).abs() < 1e-12, "height is the largest extent");
        assert!(hi[0] < 1.0 && hi[2] < 1.0);
        // Not mirror-symmetric: measured from the body's axis (the antenna tip, the
        // highest point), the raised left arm (+x) reaches much further out.
        let top = m
            .positions
            .iter()
            .max_by(|a, b| a[1].total_cmp(&b[1]))
            .unwrap();
        let (left_reach, right_reach) = (hi[0] - top[0], top[0] - lo[0]);
        assert!(left_reach > 1.5 * right_reach, "{left_reach} {right_reach}");
    }

    fn bounds(positions: &[[f64; 3]]) -> ([f64; 3], [f64; 3]) {
        positions.iter().fold(
            ([f64::INFINITY; 3], [f64::NEG_INFINITY; 3]),
            |(lo, hi), p| {
                (
                    std::array::from_fn(|k| lo[k].min(p[k])),
                    std::array::from_fn(|k| hi[k].max(p[k])),
                )
            },
        )
    }
}

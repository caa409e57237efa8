//! The scene prepared for tracing, and its two questions: the nearest hit
//! of a ray, and whether anything blocks a shadow ray.

use std::ops::ControlFlow;

use glam::DVec2;

use super::bvh_walk::WidenedBvh;
use super::cuboid::cuboid;
use super::hit::{better, Hit, Ray};
use super::plane::plane;
use super::sphere::{huge_sphere, sphere};
use super::triangle::{triangle_in, triangle_normal, RayFrame};
use crate::rt_scene::{Primitive, RtScene, RtSphere};

/// The scene prepared for tracing: the BVH with widened `f64` boxes.
pub struct Accel<'a> {
    pub scene: &'a RtScene,
    bvh: WidenedBvh<'a>,
}

impl<'a> Accel<'a> {
    pub fn new(scene: &'a RtScene) -> Self {
        Accel {
            scene,
            bvh: WidenedBvh::new(scene),
        }
    }

    /// The nearest hit with `t > 0`, ties to the lower object index.
    pub fn nearest(&self, ray: &Ray) -> Option<Hit> {
        let best = self.nearest_shape(ray);
        self.nearest_triangle(ray, best)
    }

    /// The nearest hit on the spheres, planes and boxes, tested one by one.
    #[inline]
    fn nearest_shape(&self, ray: &Ray) -> Option<Hit> {
        let s = self.scene;
        let mut best: Option<Hit> = None;
        // Either kind of sphere, hit at `t`: the same normal and record.
        let sphere_hit = |t: f64, sp: &RtSphere, primitive| {
            let n = (ray.origin + t * ray.dir - sp.center) / sp.radius;
            Hit {
                t,
                object: sp.object,
                material: sp.material,
                primitive,
                normal: n,
                geometric_normal: n,
                barycentrics: DVec2::ZERO,
            }
        };
        for (i, sp) in s.spheres.iter().enumerate() {
            if let Some(t) = sphere(ray, sp) {
                if better(t, sp.object, 0, best.as_ref()) {
                    best = Some(sphere_hit(t, sp, Primitive::Sphere(i as u32)));
                }
            }
        }
        for (i, huge) in s.huge_spheres.iter().enumerate() {
            if let Some(t) = huge_sphere(ray, huge) {
                if better(t, huge.sphere.object, 0, best.as_ref()) {
                    best = Some(sphere_hit(t, &huge.sphere, Primitive::HugeSphere(i as u32)));
                }
            }
        }
        for (i, pl) in s.planes.iter().enumerate() {
            if let Some(t) = plane(ray, pl) {
                if better(t, pl.object, 0, best.as_ref()) {
                    best = Some(Hit {
                        t,
                        object: pl.object,
                        material: pl.material,
                        primitive: Primitive::Plane(i as u32),
                        normal: pl.normal,
                        geometric_normal: pl.normal,
                        barycentrics: DVec2::ZERO,
                    });
                }
            }
        }
        for (i, b) in s.boxes.iter().enumerate() {
            if let Some((t, n, face)) = cuboid(ray, b) {
                if better(t, b.object, 0, best.as_ref()) {
                    best = Some(Hit {
                        t,
                        object: b.object,
                        material: b.material,
                        primitive: Primitive::Box {
                            index: i as u32,
                            face,
                        },
                        normal: n,
                        geometric_normal: n,
                        barycentrics: DVec2::ZERO,
                    });
                }
            }
        }
        best
    }

    /// `best`, or a nearer (or tying and winning) hit on a mesh triangle,
    /// found through the BVH.
    #[inline]
    fn nearest_triangle(&self, ray: &Ray, mut best: Option<Hit>) -> Option<Hit> {
        let s = self.scene;
        let frame = RayFrame::new(ray.dir);
        let t_max = best.map_or(f64::INFINITY, |b| b.t);
        self.bvh.walk(ray, t_max, |leaf, t_max| {
            for &k in leaf {
                let tri = &s.triangles[k as usize];
                let Some((t, u, v)) = triangle_in(&frame, ray, tri) else {
                    continue;
                };
                if better(t, tri.object, k, best.as_ref()) {
                    best = Some(Hit {
                        t,
                        object: tri.object,
                        material: tri.material,
                        primitive: Primitive::Triangle(k),
                        normal: triangle_normal(tri, u, v),
                        geometric_normal: tri.geometric_normal(),
                        barycentrics: DVec2::new(u, v),
                    });
                    *t_max = t;
                }
            }
            ControlFlow::Continue(())
        });
        best
    }

    /// Whether anything is hit at `0 < t < t_max` (a shadow ray).
    pub fn any(&self, ray: &Ray, t_max: f64) -> bool {
        let s = self.scene;
        let within = |t: f64| t < t_max;
        if s.spheres
            .iter()
            .any(|sp| sphere(ray, sp).is_some_and(within))
            || s.huge_spheres
                .iter()
                .any(|sp| huge_sphere(ray, sp).is_some_and(within))
            || s.planes.iter().any(|pl| plane(ray, pl).is_some_and(within))
            || s.boxes
                .iter()
                .any(|b| cuboid(ray, b).is_some_and(|(t, _, _)| within(t)))
        {
            return true;
        }
        let frame = RayFrame::new(ray.dir);
        let mut blocked = false;
        self.bvh.walk(ray, t_max, |leaf, _| {
            blocked = leaf.iter().any(|&k| {
                triangle_in(&frame, ray, &s.triangles[k as usize])
                    .is_some_and(|(t, _, _)| within(t))
            });
            if blocked {
                ControlFlow::Break(())
            } else {
                ControlFlow::Continue(())
            }
        });
        blocked
    }
}

#[cfg(test)]
mod tests {
    use super::super::test_support::{ray, unit_sphere};
    use super::super::triangle::triangle;
    use super::*;
    use crate::rt_scene::RtPlane;
    use glam::DVec3;

    fn empty_scene() -> RtScene {
        let mut scene = crate::scene::default_scene();
        scene.objects.clear();
        scene.camera.position = DVec3::ZERO;
        scene.camera.look_at = -DVec3::Z;
        RtScene::new(&scene)
    }

    #[test]
    fn ties_go_to_the_lower_object_index() {
        let mut rt = empty_scene();
        // Two coincident spheres: listed in reverse object order.
        rt.spheres = vec![
            unit_sphere(DVec3::new(0.0, 0.0, -5.0), 7),
            unit_sphere(DVec3::new(0.0, 0.0, -5.0), 3),
        ];
        // A plane through the sphere's front point at the same t, with a
        // higher object index; and one with a lower index.
        let (u, v) = crate::scene::plane_axes(DVec3::Z);
        let front = RtPlane {
            center: DVec3::new(0.0, 0.0, -4.0),
            normal: DVec3::Z,
            u,
            v,
            half_size: 10.0,
            material: 0,
            object: 9,
        };
        rt.planes = vec![front];
        let accel = Accel::new(&rt);
        let r = ray(DVec3::ZERO, -DVec3::Z);
        let hit = accel.nearest(&r).unwrap();
        assert_eq!((hit.t, hit.object), (4.0, 3));
        rt.planes[0].object = 1;
        let accel = Accel::new(&rt);
        let hit = accel.nearest(&r).unwrap();
        assert_eq!((hit.t, hit.object, hit.normal), (4.0, 1, DVec3::Z));
        // Any-hit is strict: a blocker exactly at t_max does not block.
        assert!(!accel.any(&r, 4.0));
        assert!(accel.any(&r, 4.0 + 1e-9));
    }

    #[test]
    fn bvh_traversal_equals_brute_force() {
        // A tessellated sphere and a tilted plane as meshes: every ray's
        // nearest hit through the BVH equals a loop over all triangles.
        let mut scene = crate::scene::default_scene();
        scene.camera.position = DVec3::new(0.3, 0.2, 6.0);
        for object in &mut scene.objects {
            object.shape = crate::scene::Shape::Mesh(crate::scene::tessellate(&object.shape));
        }
        let rt = RtScene::new(&scene);
        assert!(rt.triangles.len() > 1000);
        let accel = Accel::new(&rt);
        let mut hits = 0;
        for i in 0..2000 {
            let a = f64::from(i) * 0.618_033_988_749;
            let b = f64::from(i) * 0.414_213_562_373;
            let dir = DVec3::new((a.fract() - 0.5) * 1.2, (b.fract() - 0.7) * 1.0, -1.0);
            let r = ray(DVec3::ZERO, dir);
            let brute = rt
                .triangles
                .iter()
                .enumerate()
                .filter_map(|(k, t)| triangle(&r, t).map(|(t, _, _)| (t, k as u32)))
                .min_by(|x, y| x.partial_cmp(y).unwrap());
            let bvh = accel.nearest(&r).map(|h| match h.primitive {
                Primitive::Triangle(k) => (h.t, k),
                _ => unreachable!(),
            });
            assert_eq!(bvh, brute, "ray {i}");
            hits += usize::from(bvh.is_some());
            if let Some((t, _)) = brute {
                assert!(accel.any(&r, t * 1.000001));
                assert!(!accel.any(&r, t));
            }
        }
        assert!(hits > 500, "{hits} hits");
    }
}

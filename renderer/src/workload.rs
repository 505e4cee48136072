//! The tracing core's reference workload, shared by the trace bench
//! (`renderer/benches/trace.rs`), the `trace_rays` example and the peers comparison
//! (`bench/peers/`): a 200,000-triangle torus above a 100 x 100 ground rectangle, 256 x 256
//! jittered pinhole rays with times in a shutter, and for each hit one shadow ray towards a
//! directional light from [`SurfaceHit::spawn_point`](crate::accel::SurfaceHit::spawn_point).

use crate::accel::{Instance, World};
use crate::geometry::tessellate::torus;
use crate::geometry::{Plane, Ray, Shape, TriangleMesh};
use crate::hash::{hash, unit_f32};
use crate::motion::{Motion, MotionLayer};
use glam::{Vec2, Vec3, Vec3A};
use std::sync::Arc;

/// Image size in pixels (square).
pub const SIZE: u32 = 256;
/// The shutter the worlds are built for.
pub const SHUTTER: (f32, f32) = (0.0, 0.12);
/// Half the ground rectangle's side.
pub const GROUND_HALF: f32 = 50.0;

pub struct TraceWorkload {
    pub mesh: Arc<TriangleMesh>,
    /// Where the torus sits (object space is centred on it).
    pub location: Vec3,
    /// Unit direction towards the directional light.
    pub light: Vec3A,
    pub eye: Vec3A,
}

impl Default for TraceWorkload {
    fn default() -> Self {
        Self::new()
    }
}

impl TraceWorkload {
    /// The torus (500 x 200 x 2 = 200k triangles) and its BVH.
    pub fn new() -> Self {
        Self {
            mesh: Arc::new(torus(3.0, 1.0, 500, 200)),
            location: Vec3::new(0.0, 1.2, 0.0),
            light: Vec3A::new(0.4, 1.0, 0.3).normalize(),
            eye: Vec3A::new(0.0, 7.0, 9.0),
        }
    }

    /// The world with the torus moving at `velocity` and spinning at `angular_velocity`.
    pub fn world(&self, velocity: Vec3, angular_velocity: Vec3) -> World {
        let torus = Instance {
            shape: Shape::Mesh(self.mesh.clone()),
            motion: Motion {
                layers: vec![MotionLayer {
                    location: self.location,
                    velocity,
                    angular_velocity,
                    ..MotionLayer::default()
                }],
            },
            material: 0,
        };
        let ground = Instance {
            shape: Shape::Plane(Plane {
                half_extent: Some(Vec2::splat(GROUND_HALF)),
            }),
            motion: Motion::default(),
            material: 1,
        };
        World::build(vec![torus, ground], SHUTTER)
    }

    /// World-space triangles of the still torus and of the ground (two triangles, last), for
    /// tracers without instancing.
    pub fn world_triangles(&self) -> Vec<[Vec3A; 3]> {
        let offset = Vec3A::from(self.location);
        let g = [(-1.0, -1.0), (1.0, -1.0), (1.0, 1.0), (-1.0, 1.0)]
            .map(|(x, z)| Vec3A::new(x * GROUND_HALF, 0.0, z * GROUND_HALF));
        (0..self.mesh.triangle_count())
            .map(|i| self.mesh.corners(i).map(|v| v + offset))
            .chain([[g[0], g[2], g[1]], [g[0], g[3], g[2]]])
            .collect()
    }

    /// The camera ray of pixel (x, y): jittered in the pixel and in the shutter.
    pub fn camera_ray(&self, x: u32, y: u32) -> Ray {
        let h = |axis: u64| unit_f32(hash(17, &[x as u64, y as u64, axis]));
        let u = (x as f32 + h(0)) / SIZE as f32 * 2.0 - 1.0;
        let v = 1.0 - (y as f32 + h(1)) / SIZE as f32 * 2.0;
        let forward = (Vec3A::new(0.0, 1.0, 0.0) - self.eye).normalize();
        let right = forward.cross(Vec3A::Y).normalize();
        let up = right.cross(forward);
        let dir = forward + (right * u + up * v) * 0.6;
        Ray::new(self.eye, dir, SHUTTER.0 + (SHUTTER.1 - SHUTTER.0) * h(2))
    }

    /// Trace row `y`: (rays cast, primary + shadow; lit hits).
    pub fn trace_row(&self, world: &World, y: u32) -> (u64, u64) {
        let (mut rays, mut lit) = (0, 0);
        for x in 0..SIZE {
            let ray = self.camera_ray(x, y);
            rays += 1;
            if let Some(h) = world.intersect(&ray) {
                rays += 1;
                let shadow = Ray::new(h.spawn_point(self.light), self.light, ray.time);
                lit += u64::from(!world.occluded(&shadow));
            }
        }
        (rays, lit)
    }

    /// Trace the whole frame on the calling thread.
    pub fn trace_frame(&self, world: &World) -> (u64, u64) {
        (0..SIZE)
            .map(|y| self.trace_row(world, y))
            .fold((0, 0), |a, b| (a.0 + b.0, a.1 + b.1))
    }
}

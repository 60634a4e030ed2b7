//! The camera: where the picture is taken from, and where a world point lands in it.

use crate::snapshot::Snapshot;
use glam::{Mat4, Vec3, Vec4Swizzles};

/// A perspective camera.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Camera {
    /// Where it stands.
    pub eye: Vec3,
    /// What it looks at.
    pub target: Vec3,
    /// Which way is up in the picture.
    pub up: Vec3,
    /// Vertical field of view, radians.
    pub fov_y: f32,
    /// Near and far clip distances.
    pub near: f32,
    /// See `near`.
    pub far: f32,
}

impl Camera {
    /// A camera that frames all of `snapshot` in a picture of aspect `width / height`,
    /// looking down on it at about 35 degrees from a fixed side.
    ///
    /// ```
    /// # use kinetic_render::{Camera, Instance, Snapshot};
    /// # use glam::Vec3;
    /// let mut s = Snapshot::new(Vec3::Z);
    /// s.instances.push(Instance::ball(Vec3::new(3.0, 0.0, 0.0), 1.0, [1.0; 4]));
    /// let cam = Camera::framing(&s, 4.0 / 3.0);
    /// // The ball is in the middle of the picture.
    /// let (x, y) = cam.project(Vec3::new(3.0, 0.0, 0.0), 640, 480).unwrap();
    /// assert!((x - 320.0).abs() < 16.0 && (y - 240.0).abs() < 12.0, "{x} {y}");
    /// ```
    pub fn framing(snapshot: &Snapshot, aspect: f32) -> Camera {
        Camera::framing_all(std::slice::from_ref(snapshot), aspect)
    }

    /// A camera that frames every snapshot of a series (whose up is the first one's), so
    /// the frames can be played one after another.
    pub fn framing_all(snapshots: &[Snapshot], aspect: f32) -> Camera {
        let up = snapshots
            .first()
            .map_or(Vec3::Z, |s| s.up)
            .normalize_or(Vec3::Y);
        // A viewing direction fixed per up axis, so the frames of a series do not jitter.
        let side = up.any_orthonormal_vector();
        let across = up.cross(side);
        let back = (side * -0.55 + across * -0.75 + up * 0.62).normalize();
        let fov_y = 40f32.to_radians();
        let (lo, hi) = snapshots
            .iter()
            .filter_map(Snapshot::bounds)
            .reduce(|(a, b), (c, d)| (a.min(c), b.max(d)))
            .unwrap_or((Vec3::splat(-1.0), Vec3::ONE));
        let right = up.cross(back).normalize_or(side);
        let cam_up = back.cross(right);
        let (tan_y, tan_x) = ((fov_y * 0.5).tan(), (fov_y * 0.5).tan() * aspect);
        let mut points: Vec<Vec3> = snapshots.iter().flat_map(Snapshot::points).collect();
        if points.is_empty() {
            points = vec![lo, hi];
        }
        let depth = points
            .iter()
            .map(|p| (*p - (lo + hi) * 0.5).length())
            .fold(0.0, f32::max);
        // The least distance from `target` at which every point is in view.
        let fit = |target: Vec3| {
            let mut distance: f32 = 0.0;
            for &p in &points {
                let rel = p - target;
                let need = rel.dot(back)
                    + (rel.dot(right).abs() / tan_x).max(rel.dot(cam_up).abs() / tan_y);
                distance = distance.max(need);
            }
            distance.max(depth * 1e-3).max(1e-6)
        };
        // Centre the picture on what is drawn (perspective makes the box centre sit off
        // centre), then fit again; a 4% margin.
        let mut target = (lo + hi) * 0.5;
        for _ in 0..2 {
            let d = fit(target);
            let (mut x, mut y) = (
                (f32::INFINITY, f32::NEG_INFINITY),
                (f32::INFINITY, f32::NEG_INFINITY),
            );
            for &p in &points {
                let rel = p - target;
                let along = (d - rel.dot(back)).max(1e-6);
                let (u, v) = (rel.dot(right) / along, rel.dot(cam_up) / along);
                x = (x.0.min(u), x.1.max(u));
                y = (y.0.min(v), y.1.max(v));
            }
            target += (right * (x.0 + x.1) * 0.5 + cam_up * (y.0 + y.1) * 0.5) * d;
        }
        let distance = fit(target) * 1.04;
        let reach = points
            .iter()
            .map(|p| (*p - target).length())
            .fold(0.0, f32::max);
        Camera {
            eye: target + back * distance,
            target,
            up,
            fov_y,
            near: (distance - reach * 1.05).max(distance * 1e-3),
            far: distance + reach * 1.05,
        }
    }

    /// World to clip space for a picture of aspect `width / height`.
    pub fn view_projection(&self, aspect: f32) -> Mat4 {
        let view = glam::camera::rh::view::look_at_mat4(self.eye, self.target, self.up);
        // wgpu's clip depth runs 0..1, as DirectX's.
        let proj =
            glam::camera::rh::proj::directx::perspective(self.fov_y, aspect, self.near, self.far);
        proj * view
    }

    /// Where `point` lands in a `width` x `height` picture, in pixels from the top left
    /// (pixel centres at half-integers), or `None` behind the camera.
    pub fn project(&self, point: Vec3, width: u32, height: u32) -> Option<(f32, f32)> {
        let clip = self.view_projection(width as f32 / height as f32) * point.extend(1.0);
        if clip.w <= 0.0 {
            return None;
        }
        let ndc = clip.xy() / clip.w;
        Some((
            (ndc.x + 1.0) * 0.5 * width as f32,
            (1.0 - ndc.y) * 0.5 * height as f32,
        ))
    }
}

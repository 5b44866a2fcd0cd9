//! The blade of grass: a quadratic Bezier curve (v0 root, v1 guide, v2 tip guide) with its
//! orientation, height, width and stiffness packed into four `vec4`s (SPEC §1), and the directions
//! derived from it that physics, culling and drawing share.

use bytemuck::{Pod, Zeroable};
use glam::{Vec3, Vec4};

/// One blade as the GPU stores it: 4 × `vec4` = 64 bytes.
///
/// `v0.w` = orientation θ, `v1.w` = height h, `v2.w` = width w, `up.w` = stiffness s.
#[repr(C)]
#[derive(Clone, Copy, Debug, PartialEq, Pod, Zeroable)]
pub struct Blade {
    /// Root position (xyz) and orientation θ about `up` (w).
    pub v0: Vec4,
    /// Guide control point of the Bezier curve (xyz) and height h (w).
    pub v1: Vec4,
    /// Tip (xyz) and width w at the root (w).
    pub v2: Vec4,
    /// Unit up direction of the ground under the root (xyz) and stiffness s (w).
    pub up: Vec4,
}

const _: () = assert!(std::mem::size_of::<Blade>() == 64);

impl Blade {
    /// A blade standing in its rest pose: `v1 = v2 = v0 + h·up`.
    pub fn at_rest(root: Vec3, up: Vec3, orientation: f32, height: f32, width: f32, stiffness: f32) -> Self {
        let up = up.normalize();
        let tip = root + up * height;
        Self {
            v0: root.extend(orientation),
            v1: tip.extend(height),
            v2: tip.extend(width),
            up: up.extend(stiffness),
        }
    }

    /// The root, v0.
    pub fn root(&self) -> Vec3 {
        self.v0.truncate()
    }
    /// The guide control point, v1.
    pub fn guide(&self) -> Vec3 {
        self.v1.truncate()
    }
    /// The tip, v2.
    pub fn tip(&self) -> Vec3 {
        self.v2.truncate()
    }
    /// The unit up direction at the root.
    pub fn up(&self) -> Vec3 {
        self.up.truncate()
    }
    /// Orientation θ of the blade's face about `up`, radians.
    pub fn orientation(&self) -> f32 {
        self.v0.w
    }
    /// Height h: the length the blade keeps however it bends.
    pub fn height(&self) -> f32 {
        self.v1.w
    }
    /// Width w at the root.
    pub fn width(&self) -> f32 {
        self.v2.w
    }
    /// Stiffness s: how strongly it recovers its rest pose.
    pub fn stiffness(&self) -> f32 {
        self.up.w
    }

    /// Where the tip guide rests when no force acts: `I_v2 = v0 + h·up`.
    pub fn rest_tip(&self) -> Vec3 {
        self.root() + self.up() * self.height()
    }

    /// Unit direction across the blade's face (t1).
    pub fn width_dir(&self) -> Vec3 {
        width_direction(self.up(), self.orientation())
    }

    /// Unit direction the blade's face looks toward (f = up × t1).
    pub fn front_dir(&self) -> Vec3 {
        self.up().cross(self.width_dir()).normalize_or_zero()
    }

    /// Midpoint of the curve, `m = ¼v0 + ½v1 + ¼v2` (SPEC §3.7, §4).
    pub fn midpoint(&self) -> Vec3 {
        0.25 * self.root() + 0.5 * self.guide() + 0.25 * self.tip()
    }

    /// Point on the curve at parameter `v` (De Casteljau).
    pub fn point(&self, v: f32) -> Vec3 {
        let a = self.root().lerp(self.guide(), v);
        let b = self.guide().lerp(self.tip(), v);
        a.lerp(b, v)
    }

    /// Arc length of the curve, integrated numerically (for tests and diagnostics).
    pub fn curve_length(&self, segments: usize) -> f32 {
        let mut length = 0.0;
        let mut prev = self.point(0.0);
        for i in 1..=segments {
            let p = self.point(i as f32 / segments as f32);
            length += p.distance(prev);
            prev = p;
        }
        length
    }
}

/// A unit tangent of the surface with normal `up`, continuous over the sphere except at one
/// pole (Duff et al. 2017, "Building an orthonormal basis, revisited"). \[D\]'s
/// `up × normalize(sinθ, sinθ+cosθ, cosθ)` degenerates for some normals; this does not.
pub fn surface_tangent(up: Vec3) -> (Vec3, Vec3) {
    let sign = if up.z >= 0.0 { 1.0 } else { -1.0 };
    let a = -1.0 / (sign + up.z);
    let b = up.x * up.y * a;
    let t = Vec3::new(1.0 + sign * up.x * up.x * a, sign * b, -sign * up.x);
    let bt = Vec3::new(b, sign + up.y * up.y * a, -up.y);
    (t, bt)
}

/// Width direction t1: the surface tangent rotated by θ about `up`. Mirrored in the core's blade.wesl.
pub fn width_direction(up: Vec3, orientation: f32) -> Vec3 {
    let (t, b) = surface_tangent(up);
    (t * orientation.cos() + b * orientation.sin()).normalize_or_zero()
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn directions_are_orthonormal_for_any_up() {
        for up in [
            Vec3::Y,
            Vec3::X,
            -Vec3::Z,
            Vec3::Z,
            Vec3::new(0.3, -0.9, 0.1).normalize(),
        ] {
            for i in 0..8 {
                let b = Blade::at_rest(Vec3::ZERO, up, i as f32 * 0.8, 1.0, 0.1, 10.0);
                let t1 = b.width_dir();
                let f = b.front_dir();
                assert!((t1.length() - 1.0).abs() < 1e-5, "t1 not unit for {up}");
                assert!(t1.dot(up).abs() < 1e-5, "t1 not tangent for {up}");
                assert!(f.dot(t1).abs() < 1e-5 && (f.length() - 1.0).abs() < 1e-5);
            }
        }
    }

    #[test]
    fn rest_blade_is_straight_and_h_long() {
        let b = Blade::at_rest(Vec3::new(1.0, 2.0, 3.0), Vec3::Y, 0.5, 1.7, 0.1, 9.0);
        assert_eq!(b.rest_tip(), Vec3::new(1.0, 3.7, 3.0));
        assert!((b.curve_length(64) - 1.7).abs() < 1e-4);
    }
}

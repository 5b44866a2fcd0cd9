//! A wgpu application's camera in sward's terms: wgpu's clip space has y up and either depth
//! direction; sward's has y down (Vulkan's) and forward depth, which it culls with.

use glam::Mat4;
use sward_core::camera::DepthDirection;

/// sward's projection for a wgpu application's `projection` (clip space y up, depth 0..1 running
/// `direction`): y turned down, and a reversed depth turned forward (`z' = w − z`, so near and
/// far — infinite included — stay where they were). Hand it with the view matrix to
/// [`sward_core::FrameDesc::with_view_projection`]; the renderer mirrors its depths back into
/// a reversed target, where they equal the application's own.
pub fn sward_projection(projection: Mat4, direction: DepthDirection) -> Mat4 {
    let rows = projection.transpose();
    let depth = match direction {
        DepthDirection::Forward => rows.z_axis,
        DepthDirection::Reverse => rows.w_axis - rows.z_axis,
    };
    Mat4::from_cols(rows.x_axis, -rows.y_axis, depth, rows.w_axis).transpose()
}

#[cfg(test)]
mod tests {
    use glam::Vec3;

    use super::*;

    /// Clip space to (x, y, depth) after the divide.
    fn ndc(m: Mat4, p: Vec3) -> Vec3 {
        let c = m * p.extend(1.0);
        c.truncate() / c.w
    }

    #[test]
    fn a_reversed_projection_becomes_sward_s_forward_one_with_the_same_lens() {
        let (fov, aspect, near, far) = (0.9, 16.0 / 9.0, 0.1, 200.0);
        let reversed = glam::camera::rh::proj::directx::perspective(fov, aspect, far, near);
        let ours = sward_projection(reversed, DepthDirection::Reverse);
        let expected = glam::camera::rh::proj::directx::perspective(fov, aspect, near, far);
        for p in [
            Vec3::new(0.3, -0.2, -1.0),
            Vec3::new(-4.0, 2.0, -50.0),
            Vec3::new(1.0, 1.0, -150.0),
        ] {
            let (a, b) = (ndc(ours, p), ndc(expected, p));
            // x as wgpu's, y turned down, depth forward and equal to 1 − the application's.
            assert!((a.x - b.x).abs() < 1e-5 && (a.y + b.y).abs() < 1e-5, "{a} vs {b}");
            assert!((a.z - b.z).abs() < 1e-5, "{a} vs {b}");
            assert!((a.z - (1.0 - ndc(reversed, p).z)).abs() < 1e-6);
        }
    }

    #[test]
    fn an_infinite_reversed_projection_reads_as_sward_s_camera_with_its_near_plane() {
        let near = 0.1;
        let bevy_like = glam::camera::rh::proj::directx::perspective_infinite_reverse(0.8, 1.5, near);
        let ours = sward_projection(bevy_like, DepthDirection::Reverse);
        let camera = sward_core::FrameCamera::from_matrices(Mat4::IDENTITY, ours, 720);
        assert!((camera.near - near).abs() < 1e-6, "near {}", camera.near);
        assert!(camera.far > 1e30, "far {}", camera.far);
        // A point on the near plane lands at depth 0, one far away near 1.
        assert!(ndc(ours, Vec3::new(0.0, 0.0, -near)).z.abs() < 1e-6);
        assert!(ndc(ours, Vec3::new(0.0, 0.0, -1e5)).z > 0.999);
    }

    #[test]
    fn a_forward_projection_only_turns_y_down() {
        let p = glam::camera::rh::proj::directx::perspective(1.0, 1.0, 0.5, 80.0);
        let ours = sward_projection(p, DepthDirection::Forward);
        let q = Vec3::new(0.5, 0.7, -3.0);
        let (a, b) = (ndc(ours, q), ndc(p, q));
        assert!((a.x - b.x).abs() < 1e-6 && (a.y + b.y).abs() < 1e-6 && (a.z - b.z).abs() < 1e-6);
    }
}

//! A pinhole camera model: intrinsics, projection of points in the camera frame,
//! and the ray through each pixel. Camera frame: optical axis +x, image right is
//! -y, image up is +z. Pixel (col, row) has its centre at (col + 0.5, row + 0.5),
//! rows counting down from the top.

/// Intrinsics of a pinhole camera with square pixels and a centred principal point.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct CameraIntrinsics {
    /// Image width, px.
    pub width_px: u32,
    /// Image height, px.
    pub height_px: u32,
    /// Horizontal field of view, degrees.
    pub hfov_deg: f64,
    /// Vertical field of view, degrees.
    pub vfov_deg: f64,
}

impl Default for CameraIntrinsics {
    /// The ERS-7's camera at 208 x 160, 56.9 x 45.2 degrees.
    fn default() -> Self {
        Self {
            width_px: 208,
            height_px: 160,
            hfov_deg: 56.9,
            vfov_deg: 45.2,
        }
    }
}

impl CameraIntrinsics {
    /// Horizontal focal length, px.
    pub fn fx(&self) -> f64 {
        0.5 * f64::from(self.width_px) / (0.5 * self.hfov_deg.to_radians()).tan()
    }

    /// Vertical focal length, px.
    pub fn fy(&self) -> f64 {
        0.5 * f64::from(self.height_px) / (0.5 * self.vfov_deg.to_radians()).tan()
    }

    /// The image position `[u, v]` (px, u right, v down) of a point in the camera
    /// frame, or `None` if it is behind the camera or outside the image.
    pub fn project(&self, p: [f64; 3]) -> Option<[f64; 2]> {
        let [x, y, z] = p;
        if x <= 1e-9 {
            return None;
        }
        let u = 0.5 * f64::from(self.width_px) - self.fx() * y / x;
        let v = 0.5 * f64::from(self.height_px) - self.fy() * z / x;
        let inside = (0.0..=f64::from(self.width_px)).contains(&u)
            && (0.0..=f64::from(self.height_px)).contains(&v);
        inside.then_some([u, v])
    }

    /// The direction (camera frame, not normalised) of the ray through the centre
    /// of pixel `(col, row)`.
    pub fn pixel_ray(&self, col: u32, row: u32) -> [f64; 3] {
        self.pixel_rays().ray(col, row)
    }

    /// The rays through pixels, with the focal lengths worked out once (for
    /// loops over many pixels).
    pub fn pixel_rays(&self) -> PixelRays {
        PixelRays {
            half_size: [
                0.5 * f64::from(self.width_px),
                0.5 * f64::from(self.height_px),
            ],
            focal: [self.fx(), self.fy()],
        }
    }

    /// The horizontal angle (rad, left positive) of image column position `u`.
    pub fn bearing_of_column(&self, u: f64) -> f64 {
        ((0.5 * f64::from(self.width_px) - u) / self.fx()).atan()
    }
}

/// The rays through a camera's pixels (see [`CameraIntrinsics::pixel_rays`]).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct PixelRays {
    half_size: [f64; 2],
    focal: [f64; 2],
}

impl PixelRays {
    /// The direction (camera frame, not normalised) of the ray through the centre
    /// of pixel `(col, row)`.
    pub fn ray(&self, col: u32, row: u32) -> [f64; 3] {
        let u = f64::from(col) + 0.5 - self.half_size[0];
        let v = f64::from(row) + 0.5 - self.half_size[1];
        [1.0, -u / self.focal[0], -v / self.focal[1]]
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_band_seen_head_on_spans_f_h_over_d() {
        let c = CameraIntrinsics::default();
        let (h, d) = (0.2, 1.5);
        let top = c.project([d, 0.0, h / 2.0]).expect("visible");
        let bottom = c.project([d, 0.0, -h / 2.0]).expect("visible");
        assert!(((bottom[1] - top[1]) - c.fy() * h / d).abs() < 1e-9);
        assert!((c.fy() - 192.0).abs() < 1.0, "fy {}", c.fy());
    }

    #[test]
    fn points_behind_or_outside_are_not_seen() {
        let c = CameraIntrinsics::default();
        assert!(c.project([-1.0, 0.0, 0.0]).is_none());
        assert!(c.project([0.0, 0.0, 0.0]).is_none());
        assert!(c.project([1.0, 2.0, 0.0]).is_none()); // far to the left
        assert!(c.project([1.0, 0.0, -1.0]).is_none()); // far below
        assert_eq!(c.project([1.0, 0.0, 0.0]), Some([104.0, 80.0]));
    }

    #[test]
    fn pixel_rays_project_back_to_their_pixels() {
        let c = CameraIntrinsics::default();
        for (col, row) in [(0, 0), (103, 79), (207, 159), (50, 120)] {
            let r = c.pixel_ray(col, row);
            let p = c
                .project([2.0 * r[0], 2.0 * r[1], 2.0 * r[2]])
                .expect("visible");
            assert!(
                (p[0] - (f64::from(col) + 0.5)).abs() < 1e-9
                    && (p[1] - (f64::from(row) + 0.5)).abs() < 1e-9
            );
        }
    }
}

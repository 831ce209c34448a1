//! The viewer's moving camera, driven by the tracer's camera model.
//!
//! The pose is NFF's: eye $C_p$, a unit view direction $C_d$, the scene's up vector and
//! the vertical angle of view. Each change is made along the axes of
//! [`Camera`]: *move* along $C_d$, *strafe* along $C_l$ (to the image's
//! right), *rise* along $C_u$; *yaw* turns $C_d$ about the scene's up vector (so the
//! horizon stays level), *pitch* about $C_l$, and *zoom* scales the angle of view.

use tracer::scene::desc::CameraDesc;
use tracer::Camera;
use vecexpr::{vec3, Expr, Vec3};

/// Pitch stops this many degrees short of the up vector, where yaw would degenerate.
const PITCH_MARGIN_DEG: f64 = 1.0;
/// Narrowest and widest angle of view, in degrees.
pub const ANGLE_RANGE: (f64, f64) = (1.0, 170.0);

/// A camera pose that can be moved, turned and zoomed, and reset to the scene's.
#[derive(Clone, Debug, PartialEq)]
pub struct FlyCamera {
    home: CameraDesc,
    from: Vec3<f64>,
    dir: Vec3<f64>,
    up: Vec3<f64>,
    angle_deg: f64,
}

fn v(p: [f64; 3]) -> Vec3<f64> {
    vec3(p[0], p[1], p[2])
}

fn arr(p: &Vec3<f64>) -> [f64; 3] {
    [p[0], p[1], p[2]]
}

/// Rotates `p` by `angle` radians about the unit `axis` (Rodrigues' rotation formula).
fn rotate(p: &Vec3<f64>, axis: &Vec3<f64>, angle: f64) -> Vec3<f64> {
    let (s, c) = angle.sin_cos();
    (p.scale(c) + axis.cross(p).scale(s) + axis.scale(axis.dot(p) * (1.0 - c))).eval()
}

impl FlyCamera {
    /// Starts at the scene's camera.
    pub fn new(home: &CameraDesc) -> Self {
        // Camera::new's choice of up when `up` is degenerate is kept by taking its C_u.
        let cam = Camera::<f64>::new(home, 1, 1);
        let mut up = v(home.up);
        if cam.dir().cross(&up).length_squared() <= 1e-24 {
            up = cam.up().normalize().eval();
        }
        Self {
            home: home.clone(),
            from: v(home.from),
            dir: *cam.dir(),
            up: up.normalize().eval(),
            angle_deg: home.angle_deg,
        }
    }

    /// Back to the scene's camera.
    pub fn reset(&mut self) {
        *self = Self::new(&self.home);
    }

    /// The pose as an NFF camera: the scene's own camera, exactly as the file gives it,
    /// while the pose is the one [`FlyCamera::new`] started at (so the still image equals
    /// `tracer render` of the scene bit for bit); once moved, `at` is one unit along the
    /// view direction and `up` the scene's, normalised.
    pub fn desc(&self) -> CameraDesc {
        if *self == Self::new(&self.home) {
            return self.home.clone();
        }
        CameraDesc {
            from: arr(&self.from),
            at: arr(&(&self.from + &self.dir).eval()),
            up: arr(&self.up),
            angle_deg: self.angle_deg,
            ..self.home.clone()
        }
    }

    /// The tracer's camera for this pose and a `width` x `height` image.
    pub fn camera<T: vecexpr::Real>(&self, width: u32, height: u32) -> Camera<T> {
        Camera::new(&self.desc(), width, height)
    }

    /// Unit $C_d$, $C_l$ and $C_u$ (forward, right, image up).
    fn axes(&self) -> (Vec3<f64>, Vec3<f64>, Vec3<f64>) {
        let cam = Camera::<f64>::new(&self.desc(), 1, 1);
        (
            *cam.dir(),
            cam.left().normalize().eval(),
            cam.up().normalize().eval(),
        )
    }

    /// Distance from the eye to the scene camera's `at`, a natural unit of speed.
    pub fn scale(&self) -> f64 {
        (v(self.home.at) - v(self.home.from)).length().max(1e-9)
    }

    /// Moves `forward` along $C_d$, `right` along $C_l$ and `rise` along $C_u$.
    pub fn translate(&mut self, forward: f64, right: f64, rise: f64) {
        let (d, l, u) = self.axes();
        self.from = (&self.from + d.scale(forward) + l.scale(right) + u.scale(rise)).eval();
    }

    /// Turns right by `yaw` degrees (about the scene's up vector) and up by `pitch`
    /// degrees (about $C_l$); pitch stops just short of straight up or down.
    pub fn turn(&mut self, yaw_deg: f64, pitch_deg: f64) {
        if yaw_deg != 0.0 {
            self.dir = rotate(&self.dir, &self.up, -yaw_deg.to_radians())
                .normalize()
                .eval();
        }
        if pitch_deg != 0.0 {
            let elevation = self.dir.dot(&self.up).clamp(-1.0, 1.0).asin().to_degrees();
            let limit = 90.0 - PITCH_MARGIN_DEG;
            let target = (elevation + pitch_deg).clamp(-limit, limit);
            let (_, l, _) = self.axes();
            self.dir = rotate(&self.dir, &l, (target - elevation).to_radians())
                .normalize()
                .eval();
        }
    }

    /// Multiplies the angle of view by `factor` (below 1 zooms in), within
    /// [`ANGLE_RANGE`].
    pub fn zoom(&mut self, factor: f64) {
        self.set_angle(self.angle_deg * factor);
    }

    /// Sets the vertical angle of view in degrees, within [`ANGLE_RANGE`].
    pub fn set_angle(&mut self, deg: f64) {
        self.angle_deg = deg.clamp(ANGLE_RANGE.0, ANGLE_RANGE.1);
    }

    /// The vertical angle of view in degrees.
    pub fn angle_deg(&self) -> f64 {
        self.angle_deg
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn home() -> CameraDesc {
        CameraDesc {
            from: [0.0, -10.0, 2.0],
            at: [0.0, 0.0, 2.0],
            up: [0.0, 0.0, 1.0],
            angle_deg: 40.0,
            hither: 0.01,
            resolution: (64, 48),
        }
    }

    fn close(a: [f64; 3], b: [f64; 3]) -> bool {
        a.iter().zip(b).all(|(x, y)| (x - y).abs() < 1e-9)
    }

    #[test]
    fn starts_at_the_scene_camera() {
        let c = FlyCamera::new(&home());
        // Unmoved, the scene's camera exactly; moved, `at` one unit ahead.
        assert_eq!(c.desc(), home());
        assert_eq!(c.scale(), 10.0);
        let mut moved = c.clone();
        moved.translate(0.0, 0.0, 0.0);
        assert_eq!(moved.desc(), home());
        moved.set_angle(30.0);
        let d = moved.desc();
        assert!(close(d.from, home().from));
        assert!(close(d.at, [0.0, -9.0, 2.0]));
        assert_eq!(d.angle_deg, 30.0);
    }

    #[test]
    fn moves_along_the_camera_axes() {
        let mut c = FlyCamera::new(&home());
        // C_d = +y, C_l (image right) = dir x up = +x, C_u = +z.
        c.translate(1.0, 2.0, 3.0);
        assert!(close(c.desc().from, [2.0, -9.0, 5.0]));
        c.reset();
        assert_eq!(c, FlyCamera::new(&home()));
    }

    #[test]
    fn yaw_is_level_and_pitch_is_clamped() {
        let mut c = FlyCamera::new(&home());
        c.turn(90.0, 0.0);
        let d = c.desc();
        // Turning right from +y about +z faces +x.
        assert!(close(d.at, [1.0, -10.0, 2.0]), "{:?}", d.at);
        c.turn(-90.0, 0.0);
        c.turn(0.0, 30.0);
        let at = c.desc().at;
        assert!((at[2] - 2.0 - 30f64.to_radians().sin()).abs() < 1e-9);
        c.turn(0.0, 500.0);
        let dz = c.desc().at[2] - 2.0;
        assert!((dz - 89f64.to_radians().sin()).abs() < 1e-9, "{dz}");
        c.turn(360.0, 0.0);
        assert!((c.desc().at[2] - 2.0 - dz).abs() < 1e-9);
    }

    #[test]
    fn zoom_scales_the_angle_within_range() {
        let mut c = FlyCamera::new(&home());
        c.zoom(0.5);
        assert_eq!(c.angle_deg(), 20.0);
        c.zoom(1e-6);
        assert_eq!(c.angle_deg(), ANGLE_RANGE.0);
        c.set_angle(1e6);
        assert_eq!(c.angle_deg(), ANGLE_RANGE.1);
    }

    #[test]
    fn degenerate_up_is_replaced() {
        let mut h = home();
        h.up = [0.0, 1.0, 0.0]; // parallel to the view
        let mut c = FlyCamera::new(&h);
        c.turn(10.0, 10.0);
        let d = c.desc();
        assert!(d.from.iter().chain(&d.at).all(|x| x.is_finite()));
    }
}

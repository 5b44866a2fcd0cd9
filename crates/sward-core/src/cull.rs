//! The CPU reference of per-blade culling (SPEC §4: orientation → frustum → distance, first failing
//! test culls) and of the tessellation level of detail (SPEC §6). The culls' visibility test
//! (`shaders/visibility.wesl`) and the tessellation level (`lod_level`, `shaders/buckets.wesl`)
//! mirror these functions.

use glam::{Mat4, Vec3, Vec4};
use serde::{Deserialize, Serialize};

use crate::blade::Blade;
use crate::validate::{finite_non_negative, Checks, Validate};

/// Each culling test's switch and parameters.
#[derive(Clone, Copy, Debug, PartialEq, Serialize, Deserialize)]
#[cfg_attr(feature = "reflect", derive(bevy_reflect::Reflect))]
#[serde(default, deny_unknown_fields)]
pub struct CullParams {
    /// Cull blades seen edge-on (SPEC §4.1).
    pub orientation: bool,
    /// Cull when `|view direction · width direction|` exceeds this (the blade is seen edge-on).
    pub orientation_threshold: f32,
    /// Cull blades outside the view frustum (SPEC §4.2).
    pub frustum: bool,
    /// Slack around the clip volume, in clip units (SPEC §4; \[D\] uses 0.5).
    pub frustum_tolerance: f32,
    /// Cull a growing share of blades with distance (SPEC §4.3).
    pub distance: bool,
    /// Number of distance buckets n.
    pub distance_levels: u32,
    /// Distance d_max at which every blade is culled.
    pub distance_max: f32,
    /// Skip whole tiles outside the view (SPEC §4's tile level).
    pub tiles: bool,
    /// Tiles within this many units of the view are simulated though not drawn, so grass coming
    /// into view has already settled.
    pub tile_margin: f32,
    /// Cull blades hidden behind occluders (ground, terrain, colliders) by a depth pyramid.
    pub occlusion: bool,
    /// A blade point counts as hidden only this far (units of view depth) behind the occluder.
    pub occlusion_tolerance: f32,
    /// Grass hides grass: this many of the nearest blades the last frame drew are drawn (a
    /// little narrower) into the depth pyramid beside the ground and the colliders, and a blade
    /// is culled only if its whole screen box lies behind them. 0: only the ground and the
    /// colliders occlude, tested at three points of each blade (SPEC §4). `auto` (the default)
    /// follows the field's density.
    pub blade_occluders: BladeOccluders,
}

/// How many of the nearest visible blades the depth pyramid holds (`cull.blade_occluders`):
/// `"auto"` or a count in the scene file (and so in messages: `Debug` writes it the same way).
#[derive(Clone, Copy, PartialEq, Eq)]
#[cfg_attr(feature = "reflect", derive(bevy_reflect::Reflect))]
pub enum BladeOccluders {
    /// As many as the field's density asks (`resolve`).
    Auto,
    /// This many; 0: none.
    Count(u32),
}

impl BladeOccluders {
    /// The fewest blades `Auto` draws.
    pub const AUTO_FLOOR: u32 = 16384;

    /// The count for a field of `blades_per_unit2` blades per square unit of ground. `Auto`:
    /// the blades of one square unit, at least `AUTO_FLOOR`. Measured on the H100 with the
    /// cis565 camera (eye at 1 in blades 1.3–2.5 tall, docs/benchmarks-history.md, "Grass hides grass"): at
    /// 18.6k blades per unit² 16384 hide all that more would (19.7 ms against 20.1 with 65536);
    /// at 74.6k the nearest 16384 are too thin a wall (135.6 ms) and 65536 or 131072 are what
    /// it takes (38.1 / 38.8 ms); on the shipped scenes (100–460 per unit²) every count above
    /// the floor only costs the pyramid pass more.
    pub fn resolve(self, blades_per_unit2: f32) -> u32 {
        match self {
            BladeOccluders::Count(n) => n,
            // The cast saturates: no budget is more than every blade.
            BladeOccluders::Auto => (blades_per_unit2.max(0.0).ceil() as u32).max(Self::AUTO_FLOOR),
        }
    }

    /// Whether any blade occludes.
    pub fn any(self) -> bool {
        self != BladeOccluders::Count(0)
    }
}

impl std::fmt::Display for BladeOccluders {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        match self {
            BladeOccluders::Auto => write!(f, "auto"),
            BladeOccluders::Count(n) => write!(f, "{n}"),
        }
    }
}

impl std::fmt::Debug for BladeOccluders {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        std::fmt::Display::fmt(self, f)
    }
}

impl Serialize for BladeOccluders {
    fn serialize<S: serde::Serializer>(&self, s: S) -> Result<S::Ok, S::Error> {
        match self {
            BladeOccluders::Auto => s.serialize_str("auto"),
            BladeOccluders::Count(n) => s.serialize_u32(*n),
        }
    }
}

impl<'de> Deserialize<'de> for BladeOccluders {
    fn deserialize<D: serde::Deserializer<'de>>(d: D) -> Result<Self, D::Error> {
        #[derive(Deserialize)]
        #[serde(untagged)]
        enum Written {
            Count(u32),
            Word(String),
        }
        let wrong = || serde::de::Error::custom("cull.blade_occluders is \"auto\" or a count of blades ≥ 0");
        match Written::deserialize(d).map_err(|_| wrong())? {
            Written::Count(n) => Ok(BladeOccluders::Count(n)),
            Written::Word(w) if w == "auto" => Ok(BladeOccluders::Auto),
            Written::Word(_) => Err(wrong()),
        }
    }
}

impl Default for CullParams {
    fn default() -> Self {
        Self {
            orientation: true,
            orientation_threshold: 0.9,
            frustum: true,
            frustum_tolerance: 0.5,
            distance: true,
            distance_levels: 100,
            distance_max: 100.0,
            tiles: true,
            tile_margin: 2.0,
            occlusion: true,
            occlusion_tolerance: 0.1,
            blade_occluders: BladeOccluders::Auto,
        }
    }
}

impl CullParams {
    /// All tests off: every blade is drawn.
    pub fn none() -> Self {
        Self {
            orientation: false,
            frustum: false,
            distance: false,
            tiles: false,
            occlusion: false,
            ..Self::default()
        }
    }

    /// The `CULL_*` flags of the tests that are on (`FrameUniforms::modes.x`).
    pub fn bits(&self) -> u32 {
        use crate::flags::{when, CULL_DISTANCE, CULL_FRUSTUM, CULL_OCCLUSION, CULL_ORIENTATION, CULL_TILES};
        when(self.orientation, CULL_ORIENTATION)
            | when(self.frustum, CULL_FRUSTUM)
            | when(self.distance, CULL_DISTANCE)
            | when(self.tiles, CULL_TILES)
            | when(self.occlusion, CULL_OCCLUSION)
    }
}

/// Why a blade was culled, or that it was not.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum CullVerdict {
    /// Drawn.
    Visible,
    /// Seen edge-on.
    Orientation,
    /// Outside the view frustum.
    Frustum,
    /// Dropped by distance culling.
    Distance,
}

/// The culling decision for blade `id` (its index in the field) seen from `eye` through `view_proj`.
pub fn cull_blade(blade: &Blade, id: u32, eye: Vec3, view_proj: &Mat4, params: &CullParams) -> CullVerdict {
    cull_blade_loosened(blade, id, eye, view_proj, params, 0.0)
}

/// As [`cull_blade`] with every threshold moved by `slack` toward keeping the blade (negative:
/// toward culling). Two calls with ±slack that disagree mark a blade on a threshold, where the
/// GPU's rounding may legitimately decide otherwise.
pub fn cull_blade_loosened(
    blade: &Blade,
    id: u32,
    eye: Vec3,
    view_proj: &Mat4,
    params: &CullParams,
    slack: f32,
) -> CullVerdict {
    cull_blade_casting(blade, id, eye, view_proj, params, None, slack)
}

/// Blades near the eye cast shadows (the sun's near cascade): `toward_sun`, and the cascade's
/// `reach` around the eye.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct ShadowCasting {
    /// Unit direction toward the sun.
    pub toward_sun: Vec3,
    /// Radius around the eye within which blades cast shadows.
    pub reach: f32,
}

impl ShadowCasting {
    /// Where the shadow of the blade's tip falls on the ground through its root: the sun's ray
    /// back from the tip, at most five heights long (a low sun).
    pub fn tip_shadow(&self, blade: &Blade) -> Vec3 {
        let up = blade.up();
        let sun = self.toward_sun.normalize_or_zero();
        let height = (blade.tip() - blade.root()).dot(up);
        blade.tip() - sun * (height / sun.dot(up).max(0.2))
    }
}

/// As [`cull_blade_loosened`], where blades within `casting.reach` of the eye cast shadows: the
/// frustum test keeps a blade whose tip's shadow lies in view though the blade does not, so
/// blades just off screen still cast their shadows into it.
pub fn cull_blade_casting(
    blade: &Blade,
    id: u32,
    eye: Vec3,
    view_proj: &Mat4,
    params: &CullParams,
    casting: Option<ShadowCasting>,
    slack: f32,
) -> CullVerdict {
    if params.orientation && seen_edge_on(blade, eye, params.orientation_threshold + slack) {
        return CullVerdict::Orientation;
    }
    if params.frustum && outside_frustum(blade, view_proj, params.frustum_tolerance, slack) {
        let shadow_seen = casting.is_some_and(|c| {
            blade.root().distance(eye) < c.reach + slack
                && inside_clip(
                    *view_proj * c.tip_shadow(blade).extend(1.0),
                    params.frustum_tolerance,
                    slack,
                )
        });
        if !shadow_seen {
            return CullVerdict::Frustum;
        }
    }
    if params.distance && thinned_by_distance(blade, id, eye, params, slack) {
        return CullVerdict::Distance;
    }
    CullVerdict::Visible
}

/// Orientation test: a blade seen along its width direction is a sliver; cull it.
/// (The paper's inequality is the KEEP condition; inverting it culls ~71% instead of ~29%.)
fn seen_edge_on(blade: &Blade, eye: Vec3, threshold: f32) -> bool {
    let view_dir = (blade.root() - eye).normalize_or_zero();
    view_dir.dot(blade.width_dir()).abs() > threshold
}

/// Frustum test: cull only when all three curve points are outside the tolerant clip volume.
fn outside_frustum(blade: &Blade, view_proj: &Mat4, tolerance: f32, slack: f32) -> bool {
    [blade.root(), blade.midpoint(), blade.tip()]
        .iter()
        .all(|p| !inside_clip(*view_proj * p.extend(1.0), tolerance, slack))
}

/// Vulkan's clip volume: −w ≤ x, y ≤ w and 0 ≤ z ≤ w, widened by `tolerance` (and by `slack`
/// scaled to the point's depth, as rounding in clip space grows with w).
pub fn inside_clip(clip: Vec4, tolerance: f32, slack: f32) -> bool {
    let t = tolerance + slack * clip.w.abs().max(1.0);
    let limit = clip.w + t;
    clip.x >= -limit && clip.x <= limit && clip.y >= -limit && clip.y <= limit && clip.z >= -t && clip.z <= limit
}

/// Distance test: of every n blades (by id), keep fewer the farther they are from the eye, measured
/// in the ground plane. Ids are shuffled at generation, so thinning shows no pattern.
fn thinned_by_distance(blade: &Blade, id: u32, eye: Vec3, params: &CullParams, slack: f32) -> bool {
    let up = blade.up();
    let rel = blade.root() - eye;
    let d_proj = (rel - up * rel.dot(up)).length();
    let n = params.distance_levels.max(1);
    let kept = (n as f32 * (1.0 - d_proj / params.distance_max) + slack * n as f32).ceil();
    (id % n) as f32 >= kept
}

/// Tessellation level of detail (SPEC §6): smooth in distance, from `max_level` up close to
/// `min_level` beyond `far`.
#[derive(Clone, Copy, Debug, PartialEq, Serialize, Deserialize)]
#[cfg_attr(feature = "reflect", derive(bevy_reflect::Reflect))]
#[serde(default, deny_unknown_fields)]
pub struct LodParams {
    /// Tessellation level beyond `far`.
    pub min_level: f32,
    /// Tessellation level up to `near`.
    pub max_level: f32,
    /// Distance up to which blades get `max_level`.
    pub near: f32,
    /// Distance from which blades get `min_level`.
    pub far: f32,
    /// Where the compute draw route hands the blades over from the hardware (strips) to
    /// compute splatting: blades of the distance buckets wholly beyond it are splatted.
    pub splat_distance: f32,
    /// Whether the compute route rasterizes blades by compute from `strip_distance` to
    /// `splat_distance` (else strips reach the splats). Off by default: on the H100 it wins
    /// where blades are many and deep (cis565 2^24 blades: 158 ms against 418 tessellated) and
    /// loses on the shipped scenes (meadow 6.7 ms against 5.9 with strips; docs/benchmarks-history.md).
    pub compute_raster: bool,
    /// With `compute_raster`, blades of the buckets wholly nearer than this are still drawn
    /// by the hardware as strips (0: none). The few huge blades next to the eye are what the
    /// hardware rasterizes well; the many behind them, compute.
    pub strip_distance: f32,
}

impl Default for LodParams {
    fn default() -> Self {
        Self {
            min_level: 3.0,
            max_level: 8.0,
            near: 5.0,
            far: 15.0,
            splat_distance: 20.0,
            compute_raster: false,
            strip_distance: 6.0,
        }
    }
}

impl LodParams {
    /// The tessellation level at `distance` from the eye.
    pub fn level(&self, distance: f32) -> f32 {
        let t = ((distance - self.near) / (self.far - self.near)).clamp(0.0, 1.0);
        self.min_level + (self.max_level - self.min_level) * (1.0 - t)
    }
}

impl Validate for CullParams {
    fn validate(&self, c: &mut Checks) {
        c.check(
            self.orientation_threshold > 0.0 && self.orientation_threshold <= 1.0,
            "cull.orientation_threshold",
            self.orientation_threshold,
            "a value in (0, 1]",
        );
        c.non_negative("cull.frustum_tolerance", self.frustum_tolerance);
        c.check(
            (1..=1000).contains(&self.distance_levels),
            "cull.distance_levels",
            self.distance_levels,
            "1 to 1000 buckets",
        );
        c.check(
            self.distance_max > 0.0 && self.distance_max.is_finite(),
            "cull.distance_max",
            self.distance_max,
            "a positive distance",
        );
        c.check(
            finite_non_negative(self.tile_margin),
            "cull.tile_margin",
            self.tile_margin,
            "a finite distance ≥ 0",
        );
        c.check(
            finite_non_negative(self.occlusion_tolerance),
            "cull.occlusion_tolerance",
            self.occlusion_tolerance,
            "a finite depth ≥ 0",
        );
        c.check(
            self.blade_occluders.resolve(0.0) <= crate::validate::MAX_BLADES,
            "cull.blade_occluders",
            self.blade_occluders,
            "\"auto\", or 0 (only the ground and colliders occlude) to as many blades as a field may hold",
        );
    }
}

impl Validate for LodParams {
    fn validate(&self, c: &mut Checks) {
        c.check(
            self.min_level >= 1.0 && self.min_level <= self.max_level && self.max_level <= 64.0,
            "lod",
            format!("[{}, {}]", self.min_level, self.max_level),
            "levels with 1 ≤ min_level ≤ max_level ≤ 64",
        );
        c.check(
            self.near >= 0.0 && self.near < self.far,
            "lod",
            format!("[{}, {}]", self.near, self.far),
            "distances with 0 ≤ near < far",
        );
        c.check(
            self.splat_distance >= 0.0,
            "lod.splat_distance",
            self.splat_distance,
            "a distance of 0 (splat every blade on the compute route) or more",
        );
        c.check(
            self.strip_distance >= 0.0,
            "lod.strip_distance",
            self.strip_distance,
            "a distance of 0 (rasterize every near blade by compute on the compute route) or more",
        );
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::camera::Camera;

    #[test]
    fn auto_blade_occluders_follow_the_density_above_a_floor() {
        let auto = BladeOccluders::Auto;
        assert_eq!(auto.resolve(104.0), BladeOccluders::AUTO_FLOOR, "the meadow's density");
        assert_eq!(auto.resolve(74_565.0), 74_565, "cis565 at 2^24 blades");
        assert_eq!(auto.resolve(f32::INFINITY), u32::MAX);
        assert_eq!(auto.resolve(f32::NAN), BladeOccluders::AUTO_FLOOR);
        assert_eq!(BladeOccluders::Count(7).resolve(74_565.0), 7, "a count is kept");
        assert!(!BladeOccluders::Count(0).any() && auto.any());
    }

    #[test]
    fn blade_occluders_are_written_as_auto_or_a_count() {
        let cull = |text: &str| toml::from_str::<CullParams>(text).map(|c| c.blade_occluders);
        assert_eq!(cull("").unwrap(), BladeOccluders::Auto);
        assert_eq!(cull("blade_occluders = \"auto\"").unwrap(), BladeOccluders::Auto);
        assert_eq!(cull("blade_occluders = 65536").unwrap(), BladeOccluders::Count(65536));
        for wrong in ["\"many\"", "-1", "1.5"] {
            let e = cull(&format!("blade_occluders = {wrong}")).unwrap_err().to_string();
            assert!(e.contains("\"auto\" or a count of blades"), "{wrong}: {e}");
        }
        let written = toml::to_string(&CullParams::default()).unwrap();
        assert!(written.contains("blade_occluders = \"auto\""), "{written}");
    }

    fn facing_blade(orientation: f32) -> Blade {
        Blade::at_rest(Vec3::new(0.0, 0.0, 5.0), Vec3::Y, orientation, 1.0, 0.1, 10.0)
    }

    #[test]
    fn orientation_culls_edge_on_blades_only() {
        let cam = Camera {
            position: Vec3::new(0.0, 0.5, 0.0),
            target: Vec3::new(0.0, 0.5, 5.0),
            ..Camera::default()
        };
        let vp = cam.view_projection(1.0);
        let params = CullParams {
            frustum: false,
            distance: false,
            ..CullParams::default()
        };
        // width direction along view direction: edge-on
        let edge_on = (0..64)
            .map(|i| i as f32 / 64.0 * std::f32::consts::TAU)
            .find(|&th| facing_blade(th).width_dir().z.abs() > 0.99)
            .unwrap();
        let face_on = (0..64)
            .map(|i| i as f32 / 64.0 * std::f32::consts::TAU)
            .find(|&th| facing_blade(th).width_dir().z.abs() < 0.1)
            .unwrap();
        assert_eq!(
            cull_blade(&facing_blade(edge_on), 0, cam.position, &vp, &params),
            CullVerdict::Orientation
        );
        assert_eq!(
            cull_blade(&facing_blade(face_on), 0, cam.position, &vp, &params),
            CullVerdict::Visible
        );
    }

    #[test]
    fn orientation_culls_about_29_percent_of_uniform_orientations() {
        let eye = Vec3::new(0.0, 0.5, 0.0);
        let params = CullParams {
            frustum: false,
            distance: false,
            ..CullParams::default()
        };
        let n = 10_000;
        let culled = (0..n)
            .filter(|i| {
                let b = facing_blade(*i as f32 / n as f32 * std::f32::consts::TAU);
                cull_blade(&b, 0, eye, &Mat4::IDENTITY, &params) != CullVerdict::Visible
            })
            .count() as f32
            / n as f32;
        // |cos| > 0.9 ⇔ angle within acos(0.9) ≈ 25.8° of the axis: 4·25.8°/360° ≈ 0.287,
        // a bit less here because the eye sits above the blade.
        assert!((0.2..0.32).contains(&culled), "culled share {culled}");
    }

    #[test]
    fn frustum_culls_only_when_all_three_points_are_outside() {
        let cam = Camera {
            position: Vec3::ZERO,
            target: Vec3::new(0.0, 0.0, 10.0),
            ..Camera::default()
        };
        let vp = cam.view_projection(1.0);
        let params = CullParams {
            orientation: false,
            distance: false,
            frustum_tolerance: 0.0,
            ..CullParams::default()
        };
        let behind = Blade::at_rest(Vec3::new(0.0, 0.0, -5.0), Vec3::Y, 0.0, 1.0, 0.1, 10.0);
        assert_eq!(cull_blade(&behind, 0, cam.position, &vp, &params), CullVerdict::Frustum);
        // Root below the bottom edge, tip inside: kept (culling on any one point is wrong).
        let rising = Blade::at_rest(Vec3::new(0.0, -6.0, 10.0), Vec3::Y, 0.0, 3.0, 0.1, 10.0);
        assert_eq!(cull_blade(&rising, 0, cam.position, &vp, &params), CullVerdict::Visible);
    }
    #[test]
    fn a_blade_off_screen_whose_shadow_is_in_view_is_kept_only_when_it_casts() {
        let cam = Camera {
            position: Vec3::new(0.0, 1.0, 0.0),
            target: Vec3::new(0.0, 1.0, 5.0),
            ..Camera::default()
        };
        let vp = cam.view_projection(1.0);
        let frustum = CullParams {
            frustum: true,
            ..CullParams::none()
        };
        // A blade 4 units to the side at 4 ahead (the view is 1.7 wide there) under a low sun
        // on its side: its tip's shadow falls on the view's centre line.
        let blade = Blade::at_rest(Vec3::new(4.0, 0.0, 4.0), Vec3::Y, 0.0, 1.0, 0.05, 10.0);
        let toward_sun = Vec3::new(1.0, 0.25, 0.0).normalize();
        let casting = ShadowCasting {
            toward_sun,
            reach: 20.0,
        };
        assert!(
            casting.tip_shadow(&blade).x.abs() < 0.01,
            "{:?}",
            casting.tip_shadow(&blade)
        );
        assert_eq!(cull_blade(&blade, 0, cam.position, &vp, &frustum), CullVerdict::Frustum);
        let kept = cull_blade_casting(&blade, 0, cam.position, &vp, &frustum, Some(casting), 0.0);
        assert_eq!(kept, CullVerdict::Visible);
        let beyond = ShadowCasting { reach: 1.0, ..casting };
        let culled = cull_blade_casting(&blade, 0, cam.position, &vp, &frustum, Some(beyond), 0.0);
        assert_eq!(
            culled,
            CullVerdict::Frustum,
            "beyond the cascade's reach blades cast nothing"
        );
    }

    #[test]
    fn distance_thins_the_far_field_not_the_near() {
        let params = CullParams {
            orientation: false,
            frustum: false,
            distance_max: 50.0,
            ..CullParams::default()
        };
        let kept_at = |z: f32| {
            (0..1000)
                .filter(|&id| {
                    let b = Blade::at_rest(Vec3::new(0.0, 0.0, z), Vec3::Y, 0.0, 1.0, 0.1, 10.0);
                    cull_blade(&b, id, Vec3::ZERO, &Mat4::IDENTITY, &params) == CullVerdict::Visible
                })
                .count()
        };
        assert_eq!(kept_at(0.1), 1000);
        assert!((440..=560).contains(&kept_at(25.0)));
        assert_eq!(kept_at(50.0), 0);
    }

    #[test]
    fn lod_is_smooth_and_clamped() {
        let lod = LodParams::default();
        assert_eq!(lod.level(0.0), lod.max_level);
        assert_eq!(lod.level(1000.0), lod.min_level);
        let mid = lod.level((lod.near + lod.far) / 2.0);
        assert!((mid - (lod.min_level + lod.max_level) / 2.0).abs() < 1e-5);
    }
}

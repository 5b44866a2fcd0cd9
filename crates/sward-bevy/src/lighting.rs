//! Bevy's light on the grass: the sun (the brightest visible `DirectionalLight`), point and spot
//! lights (sward's lamps: the eight that matter most to the eye), the ambient light (the
//! camera's `AmbientLight`, else the `GlobalAmbientLight`), the camera's exposure and its
//! `DistanceFog`, carried each frame into sward's shading — in the units Bevy's PBR lights a
//! mesh with — so the grass beside a Bevy mesh is lit as it is. sward's blade look (translucency,
//! rounded normals, clump colour, root occlusion) stays; what lights it is Bevy's.

use bevy::color::{ColorToComponents, LinearRgba};
use bevy::light::{AmbientLight, DirectionalLight, GlobalAmbientLight, PointLight, SpotLight};
use bevy::pbr::{DistanceFog, FogFalloff};
use bevy::prelude::ReflectDefault;
use bevy::transform::components::GlobalTransform;
use sward_core::look::{Lamp, Shading, Spot};

/// What lights the grass, and who draws it.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, bevy::reflect::Reflect)]
#[reflect(Default, Clone, PartialEq)]
pub enum GrassLighting {
    /// Drawn by sward's own pass in Bevy's main pass, after the opaque meshes: every technique,
    /// lit by Bevy's lights, exposure and fog as a Bevy mesh beside the grass is lit, but with
    /// no Bevy shadows, prepass or G-buffer.
    Bevy,
    /// Drawn by sward's own pass, lit by the scene's own `[shading]` sun, sky and fog (as
    /// `sward render` draws it).
    Scene,
    /// The default: drawn by Bevy in its own passes, as a Bevy mesh: lit by Bevy's PBR (every
    /// light and its shadows, ambient light, environment maps, fog, exposure, tonemapping),
    /// casting into Bevy's shadow maps, in the prepass (TAA, SSAO) and a deferred camera's
    /// G-buffer. Every technique, on either device: the Bezier blades, the generated grass's
    /// levels and the billboards (which cast within
    /// [`Grass::shadow_distance`](crate::Grass::shadow_distance)).
    #[default]
    Pbr,
}

/// The sun: the direction toward it and its light (linear colour times lux).
#[derive(Clone, Copy, Debug, PartialEq)]
pub(crate) struct Sun {
    pub toward: glam::Vec3,
    pub lux: glam::Vec3,
}

/// The brightest of the main world's visible directional lights.
pub(crate) fn brightest_sun<'a>(
    lights: impl Iterator<Item = (&'a DirectionalLight, &'a GlobalTransform)>,
) -> Option<Sun> {
    lights
        .map(|(light, transform)| Sun {
            // A directional light shines along its forward (-Z): the sun is behind it.
            toward: transform.back().as_vec3(),
            lux: linear(light.color.into()) * light.illuminance,
        })
        .max_by(|a, b| a.lux.element_sum().total_cmp(&b.lux.element_sum()))
}

/// Bevy's point light at `transform` as a lamp, before the view's exposure: Bevy lights a mesh
/// with its lumens / 4π (candela) over the squared distance, times its diffuse colour / π.
pub(crate) fn point_lamp(light: &PointLight, transform: &GlobalTransform) -> Lamp {
    Lamp {
        position: transform.translation(),
        color: candela_over_pi(light.color, light.intensity),
        range: light.range,
        spot: None,
    }
}

/// Bevy's spot light at `transform` as a lamp (it shines along the transform's forward).
pub(crate) fn spot_lamp(light: &SpotLight, transform: &GlobalTransform) -> Lamp {
    Lamp {
        position: transform.translation(),
        color: candela_over_pi(light.color, light.intensity),
        range: light.range,
        spot: Some(Spot {
            direction: transform.forward().as_vec3(),
            inner_cos: light.inner_angle.cos(),
            outer_cos: light.outer_angle.cos(),
        }),
    }
}

fn candela_over_pi(colour: bevy::color::Color, lumens: f32) -> glam::Vec3 {
    let pi = std::f32::consts::PI;
    linear(colour.into()) * lumens / (4.0 * pi) / pi
}

/// Bevy's lighting of one view this frame.
#[cfg_attr(
    not(feature = "vulkan"),
    allow(dead_code, reason = "sward's own pass (the `vulkan` feature) lights with it")
)]
#[derive(Clone, Copy, Debug, PartialEq)]
pub(crate) struct ViewLight {
    pub sun: Option<Sun>,
    /// Linear colour times brightness (cd/m²).
    pub ambient: glam::Vec3,
    /// The camera's exposure (`Exposure::exposure`: what Bevy multiplies light by).
    pub exposure: f32,
    /// The fog's linear colour and an exponential density (none: no fog).
    pub fog: Option<(glam::Vec3, f32)>,
}

#[cfg_attr(
    not(feature = "vulkan"),
    allow(dead_code, reason = "sward's own pass (the `vulkan` feature) lights with it")
)]
impl ViewLight {
    /// The lighting of a view: the sun, the camera's ambient light where it has one (else the
    /// global one), its exposure and fog.
    pub fn of(
        sun: Option<Sun>,
        global: Option<&GlobalAmbientLight>,
        camera: Option<&AmbientLight>,
        exposure: f32,
        fog: Option<&DistanceFog>,
    ) -> ViewLight {
        let ambient = match (camera, global) {
            (Some(a), _) => linear(a.color.into()) * a.brightness,
            (None, Some(g)) => linear(g.color.into()) * g.brightness,
            (None, None) => glam::Vec3::ZERO,
        };
        ViewLight {
            sun,
            ambient,
            exposure,
            fog: fog.map(|f| (linear(f.color.into()), exponential_density(&f.falloff))),
        }
    }

    /// Light `shading` by it. Bevy lights a mesh's diffuse colour with the sun's lux × NdotL / π
    /// and the ambient light's brightness, both times the exposure; sward's blades take their
    /// albedo times the sun's colour and the sky's: so those are the sun and the sky here (the
    /// sky half of sward's hemisphere ambient, whose overhead light is `sky_zenith` × `ambient` ×
    /// 2). Without a sun the grass has only the ambient light, as a mesh would.
    pub fn light(&self, shading: &mut Shading) {
        let exposure = self.exposure;
        match self.sun {
            Some(sun) => {
                shading.light_direction = sun.toward.normalize_or(glam::Vec3::Y);
                shading.light_color = sun.lux * exposure / std::f32::consts::PI;
            }
            None => shading.light_color = glam::Vec3::ZERO,
        }
        shading.ambient = 0.5;
        shading.sky_zenith = self.ambient * exposure;
        match self.fog {
            Some((colour, density)) => {
                shading.sky_horizon = colour;
                shading.fog_density = density;
            }
            None => shading.fog_density = 0.0,
        }
    }
}

#[cfg_attr(
    not(feature = "vulkan"),
    allow(dead_code, reason = "sward's own pass (the `vulkan` feature) lights with it")
)]
/// Bevy's point and spot lights as the view's exposure shows them.
pub(crate) fn exposed(lamps: &[Lamp], exposure: f32) -> Vec<Lamp> {
    lamps
        .iter()
        .map(|l| Lamp {
            color: l.color * exposure,
            ..*l
        })
        .collect()
}

#[cfg_attr(
    not(feature = "vulkan"),
    allow(dead_code, reason = "sward's own pass (the `vulkan` feature) lights with it")
)]
/// An exponential density with the fog's half distance (where it hides half): exact for Bevy's
/// `Exponential`, the same half-way point for its other falloffs.
fn exponential_density(falloff: &FogFalloff) -> f32 {
    let ln2 = std::f32::consts::LN_2;
    match *falloff {
        FogFalloff::Exponential { density } => density,
        // Half hidden where (d·density)² = ln 2.
        FogFalloff::ExponentialSquared { density } => ln2.sqrt() * density,
        FogFalloff::Linear { start, end } => ln2 / (0.5 * (start + end)).max(1e-6),
        FogFalloff::Atmospheric { extinction, .. } => extinction.to_array().iter().sum::<f32>() / 3.0,
    }
}

fn linear(c: LinearRgba) -> glam::Vec3 {
    c.to_vec3()
}

#[cfg(test)]
mod tests {
    use super::*;
    use bevy::color::Color;

    #[test]
    fn bevy_s_light_reaches_the_grass_in_bevy_s_units() {
        let sun = Sun {
            toward: glam::Vec3::new(0.0, 2.0, 0.0),
            lux: glam::Vec3::splat(10_000.0),
        };
        let ambient = AmbientLight {
            color: Color::srgb(1.0, 0.0, 0.0),
            brightness: 100.0,
            ..Default::default()
        };
        let fog = DistanceFog {
            falloff: FogFalloff::Linear { start: 10.0, end: 30.0 },
            ..Default::default()
        };
        let view = ViewLight::of(Some(sun), None, Some(&ambient), 0.001, Some(&fog));
        let mut shading = Shading::default();
        view.light(&mut shading);
        assert_eq!(shading.light_direction, glam::Vec3::Y);
        assert!((shading.light_color.x - 10.0 / std::f32::consts::PI).abs() < 1e-4);
        assert!((shading.sky_zenith - glam::Vec3::new(0.1, 0.0, 0.0)).length() < 1e-5);
        // Linear fog from 10 to 30 hides half at 20.
        assert!((1.0 - (-shading.fog_density * 20.0).exp() - 0.5).abs() < 1e-4);
        // No sun, no fog: ambient light alone, and clear air.
        ViewLight::of(None, None, None, 0.001, None).light(&mut shading);
        assert_eq!(shading.light_color, glam::Vec3::ZERO);
        assert_eq!(shading.fog_density, 0.0);
    }

    #[test]
    fn a_spot_light_points_where_its_transform_looks() {
        let at = GlobalTransform::from(
            bevy::transform::components::Transform::from_xyz(1.0, 4.0, 2.0)
                .looking_to(-bevy::math::Vec3::Y, bevy::math::Vec3::Z),
        );
        let light = SpotLight {
            intensity: 4.0 * std::f32::consts::PI * std::f32::consts::PI,
            ..Default::default()
        };
        let lamp = spot_lamp(&light, &at);
        assert_eq!(lamp.position, glam::Vec3::new(1.0, 4.0, 2.0));
        assert!((lamp.color - glam::Vec3::ONE).length() < 1e-4, "{:?}", lamp.color);
        let spot = lamp.spot.unwrap();
        assert!((spot.direction + glam::Vec3::Y).length() < 1e-5);
        assert!(spot.inner_cos >= spot.outer_cos);
        assert_eq!(exposed(&[lamp], 0.5)[0].color, glam::Vec3::splat(0.5));
    }

    #[test]
    fn the_brightest_directional_light_is_the_sun() {
        let dim = DirectionalLight {
            illuminance: 10.0,
            ..Default::default()
        };
        let bright = DirectionalLight::default();
        let down = GlobalTransform::from(
            bevy::transform::components::Transform::default().looking_to(-bevy::math::Vec3::Y, bevy::math::Vec3::Z),
        );
        let side = GlobalTransform::from(
            bevy::transform::components::Transform::default().looking_to(bevy::math::Vec3::X, bevy::math::Vec3::Y),
        );
        let sun = brightest_sun([(&dim, &side), (&bright, &down)].into_iter()).unwrap();
        assert!((sun.toward - glam::Vec3::Y).length() < 1e-5, "{:?}", sun.toward);
        assert!(brightest_sun(std::iter::empty()).is_none());
    }
}

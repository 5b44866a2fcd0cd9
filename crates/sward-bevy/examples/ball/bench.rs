//! The ball example's `--bench`: the meadow in a headless Bevy app at 1920×1080, seen as
//! `sward bench` sees it, with sward's own measures of what it costs the app.

use std::error::Error;
use std::time::{Duration, Instant};

use bevy::camera::RenderTarget;
use bevy::prelude::*;
use bevy::time::TimeUpdateStrategy;
use sward_bevy::{GrassFrameTimes, GrassTimings, SwardPlugin};

const SIZE: [u32; 2] = [1920, 1080];

/// The image the camera draws into.
#[derive(Resource)]
struct Target(Handle<Image>);

/// How the bench's app draws.
#[derive(Clone, Copy, Debug)]
pub struct Options {
    /// The camera's samples.
    pub msaa: Msaa,
    /// Whether the meadow's grass is there.
    pub grass: bool,
    /// Whether Bevy draws it in its own passes (`GrassLighting::Pbr`).
    pub pbr: bool,
    /// Whether it casts into the sun's shadow maps (there).
    pub casts: bool,
    /// Whether the camera has Bevy's depth and motion-vector prepass.
    pub prepass: bool,
    /// Whether the camera is deferred (no MSAA).
    pub deferred: bool,
    /// Whether the app runs on the device Bevy opens itself (sward's portable passes) rather
    /// than the one `render_plugin` opens (sward's Vulkan renderer).
    pub bevy_device: bool,
    /// Whether a second camera, drawn after the first into a corner of its image, looks
    /// down on the field (a minimap: the grass culled for it too).
    pub minimap: bool,
}

/// Draw `frames` timed frames after `warm_up` ones (with the meadow's grass or without) and
/// print the measures; write the last frame to `out` if given.
pub fn run([warm_up, frames]: [usize; 2], options: Options, out: Option<String>) -> Result<(), Box<dyn Error>> {
    let mut meadow = super::meadow()?;
    meadow.lighting = match options.pbr {
        true => sward_bevy::GrassLighting::Pbr,
        false => sward_bevy::GrassLighting::Bevy,
    };
    let Options { msaa, grass, .. } = options;
    let msaa = if options.deferred { Msaa::Off } else { msaa };
    let step = Duration::from_secs_f32(meadow.scene.simulation.step);
    let mut app = App::new();
    app.add_plugins((
        super::shot::headless_plugins(options.bevy_device)?,
        SwardPlugin {
            timing: true,
            ..default()
        },
    ))
    // One fixed step of the grass a frame, as `sward bench` runs.
    .insert_resource(TimeUpdateStrategy::ManualDuration(step))
    .insert_resource(ClearColor(Color::srgb(0.55, 0.7, 0.9)))
    // A deferred camera renders the meshes deferred (Bevy's default is forward).
    .insert_resource(match options.deferred {
        true => bevy::pbr::DefaultOpaqueRendererMethod::deferred(),
        false => bevy::pbr::DefaultOpaqueRendererMethod::forward(),
    })
    .add_systems(
        Startup,
        move |mut commands: Commands,
              mut images: ResMut<Assets<Image>>,
              mut meshes: ResMut<Assets<Mesh>>,
              mut materials: ResMut<Assets<StandardMaterial>>| {
            let target = super::shot::target_image(&mut images, SIZE);
            commands.insert_resource(Target(target.clone()));
            let camera = commands
                .spawn((camera(&meadow.scene.camera, target.clone()), msaa))
                .id();
            if options.prepass || options.deferred {
                commands.entity(camera).insert((
                    bevy::core_pipeline::prepass::DepthPrepass,
                    bevy::core_pipeline::prepass::MotionVectorPrepass,
                ));
            }
            if options.deferred {
                commands
                    .entity(camera)
                    .insert(bevy::core_pipeline::prepass::DeferredPrepass);
            }
            if options.minimap {
                commands.spawn(minimap(&target, msaa));
            }
            commands.spawn(super::ground(&mut meshes, &mut materials));
            commands.spawn(super::sun());
            if grass {
                let grass = commands.spawn(meadow.clone()).id();
                if !options.casts {
                    commands.entity(grass).insert(bevy::light::NotShadowCaster);
                }
            }
        },
    );
    app.finish();
    app.cleanup();

    let timings = app.world().get_resource::<GrassTimings>().cloned();
    let timings = timings.ok_or("sward has no renderer on Bevy's device (see the log)")?;
    let route = app.world().get_resource::<sward_bevy::GrassRoute>().cloned();
    println!("the grass's route: {route:?}");
    let mut bevy_frames = Vec::with_capacity(frames);
    for k in 0..warm_up + frames {
        let start = Instant::now();
        app.update();
        if k + 1 == warm_up {
            timings.take();
        }
        if k >= warm_up {
            bevy_frames.push(ms(start.elapsed()));
        }
    }
    let measured = timings.take();
    if let Some(out) = out {
        shoot(&mut app, &out)?;
    }
    report(options, &measured, bevy_frames);
    Ok(())
}

/// A camera high over the field looking down, drawn after the main one into the top right
/// quarter of its image.
fn minimap(target: &Handle<Image>, msaa: Msaa) -> impl Bundle {
    (
        Camera3d::default(),
        Camera {
            order: 1,
            viewport: Some(bevy::camera::Viewport {
                physical_position: UVec2::new(SIZE[0] * 3 / 4, 0),
                physical_size: UVec2::new(SIZE[0] / 4, SIZE[1] / 4),
                ..default()
            }),
            ..default()
        },
        RenderTarget::Image(target.clone().into()),
        msaa,
        Transform::from_xyz(0.0, 30.0, 0.0).looking_at(Vec3::ZERO, Vec3::Z),
    )
}

/// Bevy's camera where the scene's camera is, with its field of view and near plane.
fn camera(scene: &sward_core::camera::Camera, target: Handle<Image>) -> impl Bundle {
    let at = |v: glam::Vec3| Vec3::from_array(v.to_array());
    (
        Camera3d::default(),
        RenderTarget::Image(target.into()),
        Projection::Perspective(PerspectiveProjection {
            fov: scene.fov_y_degrees.to_radians(),
            near: scene.near,
            far: scene.far,
            ..default()
        }),
        Transform::from_translation(at(scene.position)).looking_at(at(scene.target), at(scene.up)),
    )
}

/// Read the camera's image back and write it to `out`.
fn shoot(app: &mut App, out: &str) -> Result<(), Box<dyn Error>> {
    let target = app.world().resource::<Target>().0.clone();
    super::shot::shoot(app, target, SIZE, out)
}

fn ms(d: Duration) -> f64 {
    d.as_secs_f64() * 1e3
}

/// Median and 99th percentile of each measure.
fn report(options: Options, measured: &[GrassFrameTimes], bevy_frames: Vec<f64>) {
    let what = match (options.grass, options.pbr, options.casts) {
        (false, ..) => "without grass",
        (true, false, _) => "with the meadow's grass (sward's own pass)",
        (true, true, true) => "with the meadow's grass in Bevy's passes, casting",
        (true, true, false) => "with the meadow's grass in Bevy's passes, casting no shadow",
    };
    let minimap = if options.minimap { ", and a minimap camera" } else { "" };
    let camera = match (options.deferred, options.prepass) {
        (true, _) => "deferred, no MSAA".to_string(),
        (false, prepass) => {
            let samples = options.msaa.samples();
            format!(
                "{samples}× MSAA{}",
                if prepass {
                    ", depth and motion-vector prepass"
                } else {
                    ""
                }
            )
        }
    };
    let device = match options.bevy_device {
        true => "Bevy's own device (sward's portable passes; they take no timestamps)",
        false => "the device render_plugin opens (sward's Vulkan renderer)",
    };
    println!("Bevy at 1920×1080 on {device}, {camera}, the meadow's camera{minimap}, {what}");
    let gpu: Vec<_> = measured.iter().filter_map(|t| t.gpu).collect();
    let pass = |f: fn(&sward_core::timing::PassTimes) -> f64| gpu.iter().map(f).collect::<Vec<_>>();
    let host = |f: fn(&GrassFrameTimes) -> Duration| measured.iter().map(|t| ms(f(t))).collect::<Vec<_>>();
    let rows: [(&str, Vec<f64>); 11] = [
        ("GPU frame (sward's passes)", pass(|t| t.frame())),
        ("  occluders", pass(|t| t.occluders)),
        ("  trample", pass(|t| t.trample)),
        ("  simulate", pass(|t| t.simulate)),
        ("  cull", pass(|t| t.cull)),
        ("  draw", pass(|t| t.draw)),
        ("host: sward's work in Bevy's frame", host(GrassFrameTimes::host)),
        ("  extract", host(|t| t.extract)),
        (
            "  grass pass, less the wait",
            host(|t| t.draw.saturating_sub(t.gpu_wait)),
        ),
        ("  waiting for the GPU", host(|t| t.gpu_wait)),
        ("Bevy frame (App::update)", bevy_frames),
    ];
    // The frames' period over the whole run: where the GPU is the floor, its time a frame (the
    // median of App::update is not: the loop runs ahead until the frames in flight fill).
    let period = rows[10].1.iter().sum::<f64>() / rows[10].1.len().max(1) as f64;
    for (what, mut ms) in rows {
        if ms.is_empty() {
            continue;
        }
        ms.sort_by(f64::total_cmp);
        let at = |q: f64| ms[((ms.len() - 1) as f64 * q) as usize];
        println!(
            "{what}: median {:.3} ms, p99 {:.3} ms ({} frames)",
            at(0.5),
            at(0.99),
            ms.len()
        );
    }
    println!("Bevy frame period (the run's wall time / frames): {period:.3} ms");
}

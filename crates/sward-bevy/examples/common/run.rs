//! How the small examples run: in a window on the device Bevy opens, or, with `--shot OUT.png
//! [--frames N] [--size W H]`, headless on that device, every camera drawing into an image of
//! W×H (1920×1080 unless given), N frames a sixtieth of a second apart (300 unless given), the
//! last written to OUT.png. Bad flags are one sentence and exit 1.

use std::error::Error;
use std::time::Duration;

use bevy::camera::RenderTarget;
use bevy::prelude::*;
use bevy::time::TimeUpdateStrategy;
use sward_bevy::SwardPlugin;

#[path = "shot.rs"]
mod shot;
#[cfg(target_arch = "wasm32")]
#[path = "web_shots.rs"]
mod web_shots;

/// The image every camera draws into when the example runs headless.
#[derive(Resource, Clone)]
pub struct ShotTarget(pub Handle<Image>);

/// Whether the example runs headless (`--shot`), where its camera stands still and its scripted
/// input plays instead of a player's.
#[derive(Resource, Clone, Copy, Debug, PartialEq, Eq)]
pub struct Headless(pub bool);

/// The headless run the command line asks for, if any.
struct Shot {
    out: String,
    frames: u32,
    size: [u32; 2],
}

/// `--shot OUT.png [--frames N] [--size W H]` from the command line; `None` for a window.
fn shot_asked() -> Result<Option<Shot>, String> {
    let args: Vec<String> = std::env::args().skip(1).collect();
    let after = |name: &str, k: usize| args.iter().position(|a| a == name).and_then(|i| args.get(i + k));
    let number = |name: &str, k: usize| -> Result<Option<u32>, String> {
        after(name, k)
            .map(|v| v.parse().map_err(|_| format!("{name} takes whole numbers, not {v:?}")))
            .transpose()
    };
    let Some(out) = after("--shot", 1) else {
        return Ok(None);
    };
    let size = match (number("--size", 1)?, number("--size", 2)?) {
        (Some(w), Some(h)) if w > 0 && h > 0 => [w, h],
        (None, _) => [1920, 1080],
        _ => return Err("--size takes a width and a height in pixels, both above 0".into()),
    };
    let frames = number("--frames", 1)?.unwrap_or(300).max(1);
    Ok(Some(Shot {
        out: out.clone(),
        frames,
        size,
    }))
}

/// Run `app` (its systems and resources added, no plugins yet) in a window, or headless as
/// the command line asks.
pub fn run(mut app: App) -> Result<(), Box<dyn Error>> {
    let Some(shot) = shot_asked()? else {
        let window = WindowPlugin {
            primary_window: Some(window()),
            ..default()
        };
        app.add_plugins((DefaultPlugins.set(window), SwardPlugin::default()))
            .insert_resource(Headless(false))
            .add_systems(Update, quit_on_escape);
        #[cfg(target_arch = "wasm32")]
        app.add_plugins(web_shots::plugin);
        app.run();
        return Ok(());
    };
    app.add_plugins((shot::headless_plugins(true)?, SwardPlugin::default()))
        .insert_resource(Headless(true))
        .insert_resource(TimeUpdateStrategy::ManualDuration(Duration::from_secs_f64(1.0 / 60.0)))
        .add_systems(PostStartup, draw_into_target);
    let target = shot::target_image(&mut app.world_mut().resource_mut::<Assets<Image>>(), shot.size);
    app.insert_resource(ShotTarget(target.clone()));
    app.finish();
    app.cleanup();
    for _ in 0..shot.frames {
        app.update();
    }
    shot::shoot(&mut app, target, shot.size, &shot.out)
}

/// The example's window; in a web page, the page's `<canvas id="grass">`, sized as the page
/// sizes the element around it.
fn window() -> Window {
    #[cfg(target_arch = "wasm32")]
    return Window {
        canvas: Some("#grass".into()),
        fit_canvas_to_parent: true,
        ..default()
    };
    #[cfg(not(target_arch = "wasm32"))]
    Window::default()
}

/// Every camera the example spawned draws into the shot's image.
fn draw_into_target(mut commands: Commands, target: Res<ShotTarget>, cameras: Query<Entity, With<Camera>>) {
    for camera in &cameras {
        commands
            .entity(camera)
            .insert(RenderTarget::Image(target.0.clone().into()));
    }
}

/// Esc ends the example.
fn quit_on_escape(keys: Res<ButtonInput<KeyCode>>, mut exit: MessageWriter<AppExit>) {
    if keys.just_pressed(KeyCode::Escape) {
        exit.write(AppExit::Success);
    }
}

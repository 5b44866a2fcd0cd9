//! The examples' pictures handed to a web page that asks for them with `?shots=N` in its address
//! (the web example's test page does): every N frames the window's picture is captured and
//! handed to the page as a `grass-shot` event whose detail is `[width, height, RGBA bytes]`.
//! A page that does not ask gets nothing, and no frame is captured.

use bevy::prelude::*;
use bevy::render::render_resource::TextureFormat;
use bevy::render::view::screenshot::{Screenshot, ScreenshotCaptured};
use web_sys::js_sys::{Array, Uint8Array};

/// Frames between two pictures, as the page asks (the page decides which one it keeps).
#[derive(Resource)]
struct Every(u32);

/// Captures pictures where the page asks for them.
pub fn plugin(app: &mut App) {
    let search = web_sys::window().and_then(|window| window.location().search().ok());
    let every = search.as_deref().and_then(|s| s.split_once("shots=")).map(|(_, n)| {
        let digits: String = n.chars().take_while(char::is_ascii_digit).collect();
        digits.parse().unwrap_or(30).max(1)
    });
    if let Some(every) = every {
        app.insert_resource(Every(every)).add_systems(Update, capture_every);
    }
}

fn capture_every(every: Res<Every>, mut frames: Local<u32>, mut commands: Commands) {
    *frames += 1;
    if (*frames).is_multiple_of(every.0) {
        commands.spawn(Screenshot::primary_window()).observe(hand_to_page);
    }
}

/// The captured window as RGBA bytes, in a `grass-shot` event on the page's window.
fn hand_to_page(captured: On<ScreenshotCaptured>) {
    let image = &captured.image;
    let Some(mut bytes) = image.data.clone() else {
        return;
    };
    match image.texture_descriptor.format {
        TextureFormat::Rgba8Unorm | TextureFormat::Rgba8UnormSrgb => {}
        TextureFormat::Bgra8Unorm | TextureFormat::Bgra8UnormSrgb => {
            bytes.as_chunks_mut::<4>().0.iter_mut().for_each(|p| p.swap(0, 2));
        }
        other => {
            warn!("the window's format {other:?} is not handed to the page");
            return;
        }
    }
    let detail = Array::of3(
        &image.width().into(),
        &image.height().into(),
        &Uint8Array::from(bytes.as_slice()),
    );
    let init = web_sys::CustomEventInit::new();
    init.set_detail(&detail);
    let event = web_sys::CustomEvent::new_with_event_init_dict("grass-shot", &init);
    if let (Some(window), Ok(event)) = (web_sys::window(), event) {
        let _ = window.dispatch_event(&event);
    }
}

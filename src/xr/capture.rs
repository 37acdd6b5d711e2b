//! Each eye's traced image read back from the eye's own view target (the
//! texture the tracer draws into before Bevy copies it to the headset's
//! swapchain): ask with [`XrEyeCapture::request`]; a frame later both
//! eyes' RGBA bytes are in [`XrEyeCapture::take`]. Tests and
//! screenshots of a headset session use it; it costs nothing until asked.

use super::late::{ExtractedProductXrEye, ExtractedXrEye};
use bevy::prelude::*;
use bevy::render::render_resource::{
    BufferDescriptor, BufferUsages, CommandEncoderDescriptor, Extent3d, MapMode, PollType, TexelCopyBufferInfo,
    TexelCopyBufferLayout, TextureFormat,
};
use bevy::render::renderer::{RenderDevice, RenderQueue};
use bevy::render::view::ViewTarget;
use bevy::render::{Render, RenderApp, RenderSystems};
use std::path::{Path, PathBuf};
use std::sync::{Arc, Mutex};

/// One eye's image: sRGB RGBA bytes, rows top to bottom.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct XrEyeImage {
    /// Width in pixels.
    pub width: u32,
    /// Height in pixels.
    pub height: u32,
    /// `width * height * 4` bytes.
    pub rgba: Vec<u8>,
}

#[derive(Default, Debug)]
struct Slot {
    requested: bool,
    images: [Option<XrEyeImage>; 2],
}

/// Asks for both eyes' images and hands them over (shared by the main
/// and render worlds).
#[derive(Resource, Clone, Debug, Default)]
pub struct XrEyeCapture(Arc<Mutex<Slot>>);

impl XrEyeCapture {
    /// Reads both eyes back at the end of the next frame that draws them.
    pub fn request(&self) {
        if let Ok(mut s) = self.0.lock() {
            s.requested = true;
            s.images = [None, None];
        }
    }

    /// Both eyes' images (left, right), once both have come back.
    #[must_use]
    pub fn take(&self) -> Option<[XrEyeImage; 2]> {
        let mut s = self.0.lock().ok()?;
        if s.images.iter().all(Option::is_some) {
            let [l, r] = std::mem::take(&mut s.images);
            return Some([l?, r?]);
        }
        None
    }
}

/// Saves both eyes' images as `eye0.png` and `eye1.png` in `dir` (made if
/// missing); returns their paths.
///
/// # Errors
/// The folder or a file cannot be written, naming it.
pub fn save_eyes(images: &[XrEyeImage; 2], dir: &Path) -> Result<[PathBuf; 2], String> {
    std::fs::create_dir_all(dir).map_err(|e| format!("{}: {e}", dir.display()))?;
    let paths = [0, 1].map(|i| dir.join(format!("eye{i}.png")));
    for (eye, path) in images.iter().zip(&paths) {
        crate::trace::write_rgba_png(path, eye.width, eye.height, &eye.rgba)
            .map_err(|e| format!("{}: {e}", path.display()))?;
    }
    Ok(paths)
}

/// A system that asks for both eyes' images at its `at`-th run and,
/// once they are back, saves them with [`save_eyes`] in `dir`, printing
/// each file (`xr: eye (WxH) saved to PATH`) or the error. Games add it
/// to `Last` for a `--frames N --xr-capture DIR` screenshot of a headset
/// session.
///
/// ```no_run
/// use bevy::prelude::*;
/// use bevy_manifold::xr::save_eyes_at;
/// App::new().add_systems(Last, save_eyes_at(120, "eyes".into()));
/// ```
pub fn save_eyes_at(at: u32, dir: PathBuf) -> impl FnMut(Local<u32>, Res<XrEyeCapture>) + Send + Sync + 'static {
    move |mut frame: Local<u32>, capture: Res<XrEyeCapture>| {
        *frame += 1;
        if *frame == at {
            capture.request();
        }
        let Some(images) = capture.take() else { return };
        match save_eyes(&images, &dir) {
            Ok(paths) => {
                for (eye, path) in images.iter().zip(&paths) {
                    println!("xr: eye ({}x{}) saved to {}", eye.width, eye.height, path.display());
                }
            }
            Err(e) => eprintln!("error: --xr-capture {e}"),
        }
    }
}

pub(super) fn build(app: &mut App) {
    let capture = XrEyeCapture::default();
    app.insert_resource(capture.clone());
    if let Some(render_app) = app.get_sub_app_mut(RenderApp) {
        render_app.insert_resource(capture).add_systems(
            Render,
            read_back_eyes
                .after(RenderSystems::Render)
                .before(RenderSystems::Cleanup),
        );
    }
}

/// Copies each eye's view target into a buffer and reads it, when asked.
fn read_back_eyes(
    capture: Res<XrEyeCapture>,
    device: Res<RenderDevice>,
    queue: Res<RenderQueue>,
    eyes: Query<(AnyOf<(&ExtractedXrEye, &ExtractedProductXrEye)>, &ViewTarget)>,
) {
    let Ok(mut slot) = capture.0.lock() else { return };
    if !slot.requested {
        return;
    }
    for (eye, target) in &eyes {
        let index = match eye {
            (Some(e), _) => e.index,
            (None, Some(e)) => e.index,
            (None, None) => continue,
        };
        let Some(out) = slot.images.get_mut(index as usize) else {
            continue;
        };
        let texture = target.main_texture();
        let format = target.main_texture_format();
        if !matches!(format, TextureFormat::Rgba8UnormSrgb | TextureFormat::Rgba8Unorm) {
            warn!("xr: eye capture reads 8-bit RGBA targets only, this one is {format:?}");
            slot.requested = false;
            return;
        }
        let (w, h) = (texture.width(), texture.height());
        let row = (w * 4).next_multiple_of(256);
        let buffer = device.create_buffer(&BufferDescriptor {
            label: Some("xr_eye_capture"),
            size: u64::from(row) * u64::from(h),
            usage: BufferUsages::COPY_DST | BufferUsages::MAP_READ,
            mapped_at_creation: false,
        });
        let mut encoder = device.create_command_encoder(&CommandEncoderDescriptor {
            label: Some("xr_eye_capture"),
        });
        encoder.copy_texture_to_buffer(
            texture.as_image_copy(),
            TexelCopyBufferInfo {
                buffer: &buffer,
                layout: TexelCopyBufferLayout {
                    offset: 0,
                    bytes_per_row: Some(row),
                    rows_per_image: Some(h),
                },
            },
            Extent3d {
                width: w,
                height: h,
                depth_or_array_layers: 1,
            },
        );
        queue.submit([encoder.finish()]);
        let (tx, rx) = std::sync::mpsc::channel();
        buffer.slice(..).map_async(MapMode::Read, move |r| {
            let _ = tx.send(r);
        });
        if device.poll(PollType::wait_indefinitely()).is_err() || !matches!(rx.recv(), Ok(Ok(()))) {
            warn!("xr: eye {index} could not be read back");
            continue;
        }
        let data = buffer.slice(..).get_mapped_range();
        let rgba = data
            .chunks_exact(row as usize)
            .flat_map(|r| &r[..(w * 4) as usize])
            .copied()
            .collect();
        *out = Some(XrEyeImage {
            width: w,
            height: h,
            rgba,
        });
    }
    if slot.images.iter().all(Option::is_some) {
        slot.requested = false;
    }
}

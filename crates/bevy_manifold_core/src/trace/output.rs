//! Writing traced images: colour as sRGB PNG, and the id buffer as RGBA8
//! PNG (R = object, G = levels, B = low 8 bits of the cell id, A = 255).

#[cfg(feature = "png")]
use super::render::TraceImage;
use super::render::TracePixel;
#[cfg(feature = "png")]
use std::path::Path;

/// A linear colour channel as an sRGB-encoded byte (clamped to [0, 1]).
#[must_use]
pub fn srgb8(c: f32) -> u8 {
    let c = c.clamp(0.0, 1.0);
    let s = if c <= 0.003_130_8 {
        12.92 * c
    } else {
        1.055 * c.powf(1.0 / 2.4) - 0.055
    };
    (s * 255.0 + 0.5) as u8
}

/// The id-buffer RGBA of one pixel.
#[must_use]
pub fn id_pixel(p: &TracePixel) -> [u8; 4] {
    [
        p.object.min(255) as u8,
        p.levels.min(255) as u8,
        (p.cell.0 & 0xff) as u8,
        255,
    ]
}

/// Writes the colour image as an sRGB PNG.
///
/// # Errors
/// When the file cannot be written.
#[cfg(feature = "png")]
pub fn write_png(img: &TraceImage, path: &Path) -> image::ImageResult<()> {
    let buf: Vec<u8> = img
        .pixels
        .iter()
        .flat_map(|p| [srgb8(p.color[0]), srgb8(p.color[1]), srgb8(p.color[2]), 255])
        .collect();
    write_rgba_png(path, img.width, img.height, &buf)
}

/// Writes `width` x `height` RGBA8 bytes (rows top to bottom) as a PNG.
///
/// # Errors
/// When the file cannot be written, or `rgba` is not that many pixels.
#[cfg(feature = "png")]
pub fn write_rgba_png(path: &Path, width: u32, height: u32, rgba: &[u8]) -> image::ImageResult<()> {
    image::save_buffer(path, rgba, width, height, image::ExtendedColorType::Rgba8)
}

/// Writes the id buffer as an RGBA8 PNG.
///
/// # Errors
/// When the file cannot be written.
#[cfg(feature = "png")]
pub fn write_ids_png(img: &TraceImage, path: &Path) -> image::ImageResult<()> {
    let buf: Vec<u8> = img.pixels.iter().flat_map(id_pixel).collect();
    write_rgba_png(path, img.width, img.height, &buf)
}

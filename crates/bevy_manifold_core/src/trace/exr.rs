//! A traced image's linear colour as an OpenEXR file ([`exr_bytes`],
//! [`write_exr`]): the format renderers and compositors exchange HDR
//! frames in. Written here, not through the `image` crate, whose `exr`
//! feature pulls a dependency this project does not build; the file is
//! the simplest the format allows, and every reader takes it: one part,
//! scan lines top to bottom, one line per block, no compression, three
//! 32-bit float channels `B`, `G`, `R` (the names sorted, as the format
//! asks), the values unclamped (NaN and infinities written as 0).
//!
//! The layout (OpenEXR's "file layout" document): the magic number
//! 20000630 and the version word 2 (single part, scan lines); the header's
//! attributes (name, type name, byte size, value), ended by a zero byte;
//! a table of each block's offset from the start of the file; then the
//! blocks, each its line's `y`, its byte size and its pixels, channel by
//! channel. Integers and floats little-endian.

use super::render::TraceImage;
use std::path::Path;

/// OpenEXR's magic number (the first four bytes of every file).
const MAGIC: i32 = 20_000_630;

/// The channel pixel type FLOAT (32-bit IEEE).
const FLOAT: i32 = 2;

/// The bytes of `img` as an OpenEXR file (see the module).
///
/// ```
/// use bevy_manifold_core::space::cells::CellId;
/// use bevy_manifold_core::trace::{TraceImage, TracePixel, exr_bytes};
/// let pixel = TracePixel { color: [2.5, 1.0, 0.25], object: 0, levels: 0, cell: CellId(0), distance: 1.0 };
/// let img = TraceImage { width: 1, height: 1, pixels: vec![pixel] };
/// let bytes = exr_bytes(&img);
/// assert_eq!(bytes[..4], [0x76, 0x2f, 0x31, 0x01]);
/// // The one pixel, channels B, G, R, ends the file.
/// let end = bytes.len();
/// assert_eq!(bytes[end - 4..], 2.5f32.to_le_bytes());
/// ```
#[must_use]
pub fn exr_bytes(img: &TraceImage) -> Vec<u8> {
    let (w, h) = (img.width as usize, img.height as usize);
    let mut out = Vec::with_capacity(400 + h * (8 + 8 + 12 * w));
    out.extend(MAGIC.to_le_bytes());
    out.extend(2i32.to_le_bytes());
    let mut channels = Vec::new();
    for name in ["B", "G", "R"] {
        channels.extend(name.as_bytes());
        channels.push(0);
        channels.extend(FLOAT.to_le_bytes());
        // pLinear, three reserved bytes, x and y sampling.
        channels.extend([0, 0, 0, 0]);
        channels.extend(1i32.to_le_bytes());
        channels.extend(1i32.to_le_bytes());
    }
    channels.push(0);
    let window: Vec<u8> = [0, 0, img.width as i32 - 1, img.height as i32 - 1]
        .iter()
        .flat_map(|v| v.to_le_bytes())
        .collect();
    let attributes: [(&str, &str, Vec<u8>); 8] = [
        ("channels", "chlist", channels),
        // NO_COMPRESSION.
        ("compression", "compression", vec![0]),
        ("dataWindow", "box2i", window.clone()),
        ("displayWindow", "box2i", window),
        // INCREASING_Y.
        ("lineOrder", "lineOrder", vec![0]),
        ("pixelAspectRatio", "float", 1f32.to_le_bytes().to_vec()),
        (
            "screenWindowCenter",
            "v2f",
            [0f32, 0.0].iter().flat_map(|v| v.to_le_bytes()).collect(),
        ),
        ("screenWindowWidth", "float", 1f32.to_le_bytes().to_vec()),
    ];
    for (name, kind, value) in attributes {
        for s in [name, kind] {
            out.extend(s.as_bytes());
            out.push(0);
        }
        out.extend((value.len() as i32).to_le_bytes());
        out.extend(value);
    }
    out.push(0);
    let line_bytes = 12 * w;
    let table_end = out.len() + 8 * h;
    for y in 0..h {
        out.extend(((table_end + y * (8 + line_bytes)) as u64).to_le_bytes());
    }
    for (y, row) in img.pixels.chunks_exact(w.max(1)).take(h).enumerate() {
        out.extend((y as i32).to_le_bytes());
        out.extend((line_bytes as i32).to_le_bytes());
        for c in [2, 1, 0] {
            for p in row {
                let v = p.color[c];
                out.extend((if v.is_finite() { v } else { 0.0 }).to_le_bytes());
            }
        }
    }
    out
}

/// Writes `img`'s linear colour, unclamped, as an OpenEXR file
/// ([`exr_bytes`]).
///
/// # Errors
/// When the file cannot be written.
pub fn write_exr(img: &TraceImage, path: &Path) -> std::io::Result<()> {
    std::fs::write(path, exr_bytes(img))
}

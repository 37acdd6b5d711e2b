//! Writing traced images: colour as sRGB PNG, and the id buffer as RGBA8
//! PNG (R = object, G = levels, B = low 8 bits of the cell id, A = 255).

#[cfg(feature = "png")]
use super::render::TraceImage;
use super::trace::TracePixel;
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

/// Linear colours of a `from` image (row-major, `from.0 * from.1` of
/// them) resampled to `to` by the bilinear filter a GPU sampler applies:
/// texel centres at half-integers, coordinates clamped to the edge
/// texels. The upscale of a view traced at a render scale below 1.
///
/// WGSL twin: `upscale` in `bevy_manifold_gpu`'s `shaders/upscale.wgsl`
/// (there the sampler does the filtering).
///
/// ```
/// // One row of two texels, black and white, stretched to four.
/// let out = bevy_manifold_core::trace::upscale(&[[0.0; 3], [1.0; 3]], (2, 1), (4, 1));
/// let red: Vec<f32> = out.iter().map(|c| c[0]).collect();
/// assert_eq!(red, [0.0, 0.25, 0.75, 1.0]);
/// ```
#[must_use]
pub fn upscale(colors: &[[f32; 3]], from: (u32, u32), to: (u32, u32)) -> Vec<[f32; 3]> {
    let (fw, fh) = (from.0.max(1) as usize, from.1.max(1) as usize);
    if colors.len() < fw * fh {
        return Vec::new();
    }
    // The texel a coordinate falls in, its neighbour and the weight of
    // the neighbour, along one axis.
    let axis = |i: u32, out: u32, n: usize| {
        let u = (i as f32 + 0.5) / out.max(1) as f32 * n as f32 - 0.5;
        let u = u.clamp(0.0, (n - 1) as f32);
        let a = u.floor() as usize;
        (a, (a + 1).min(n - 1), u - a as f32)
    };
    let mut out = Vec::with_capacity(to.0 as usize * to.1 as usize);
    for j in 0..to.1 {
        let (y0, y1, ty) = axis(j, to.1, fh);
        for i in 0..to.0 {
            let (x0, x1, tx) = axis(i, to.0, fw);
            let at = |x: usize, y: usize| colors[y * fw + x];
            let (a, b, c, d) = (at(x0, y0), at(x1, y0), at(x0, y1), at(x1, y1));
            out.push(std::array::from_fn(|k| {
                let top = a[k] + (b[k] - a[k]) * tx;
                let bottom = c[k] + (d[k] - c[k]) * tx;
                top + (bottom - top) * ty
            }));
        }
    }
    out
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

/// Writes a traced image's linear colour, unclamped, as a Radiance HDR
/// file (RGBE: 8-bit mantissas with a shared exponent, about 1% relative
/// precision): radiance above 1 (a glow, a near light) is kept for
/// tonemapping or compositing elsewhere.
///
/// # Errors
/// When the file cannot be written.
#[cfg(feature = "png")]
pub fn write_hdr(img: &TraceImage, path: &Path) -> image::ImageResult<()> {
    let pixels: Vec<image::Rgb<f32>> = img
        .pixels
        .iter()
        .map(|p| image::Rgb(p.color.map(|c| if c.is_finite() { c.max(0.0) } else { 0.0 })))
        .collect();
    let file = std::io::BufWriter::new(std::fs::File::create(path)?);
    image::codecs::hdr::HdrEncoder::new(file).encode(&pixels, img.width as usize, img.height as usize)
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

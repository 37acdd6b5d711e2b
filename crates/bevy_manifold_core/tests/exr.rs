//! The OpenEXR writer against a file assembled here, byte by byte, from
//! the format's published layout (OpenEXR, "The OpenEXR File Layout"):
//! magic number, version, the eight required header attributes, the line
//! offset table, and uncompressed FLOAT scan lines, channels in name
//! order.

use bevy_manifold_core::space::cells::CellId;
use bevy_manifold_core::trace::{TraceImage, TracePixel, exr_bytes};

fn pixel(color: [f32; 3]) -> TracePixel {
    TracePixel {
        color,
        object: 0,
        levels: 0,
        cell: CellId(0),
        distance: 0.0,
    }
}

fn attribute(out: &mut Vec<u8>, name: &[u8], kind: &[u8], value: &[u8]) {
    out.extend_from_slice(name);
    out.push(0);
    out.extend_from_slice(kind);
    out.push(0);
    out.extend_from_slice(&(value.len() as u32).to_le_bytes());
    out.extend_from_slice(value);
}

#[test]
fn an_image_is_written_as_the_openexr_layout_says() {
    // 3 x 2 pixels, values above 1, a NaN (written as 0).
    let colors = [
        [1.0, 2.0, 3.0],
        [0.5, 0.25, 0.125],
        [40.0, 0.0, f32::NAN],
        [7.0, 8.0, 9.0],
        [0.1, 0.2, 0.3],
        [100.0, 200.0, 300.0],
    ];
    let img = TraceImage {
        width: 3,
        height: 2,
        pixels: colors.iter().map(|&c| pixel(c)).collect(),
    };
    let mut want: Vec<u8> = vec![0x76, 0x2f, 0x31, 0x01, 2, 0, 0, 0];
    let mut chlist = Vec::new();
    for name in [b'B', b'G', b'R'] {
        // name, FLOAT (2), pLinear 0 and reserved, x and y sampling 1.
        chlist.extend_from_slice(&[name, 0, 2, 0, 0, 0, 0, 0, 0, 0, 1, 0, 0, 0, 1, 0, 0, 0]);
    }
    chlist.push(0);
    assert_eq!(chlist.len(), 55);
    attribute(&mut want, b"channels", b"chlist", &chlist);
    attribute(&mut want, b"compression", b"compression", &[0]);
    let window = [0, 0, 0, 0, 0, 0, 0, 0, 2, 0, 0, 0, 1, 0, 0, 0];
    attribute(&mut want, b"dataWindow", b"box2i", &window);
    attribute(&mut want, b"displayWindow", b"box2i", &window);
    attribute(&mut want, b"lineOrder", b"lineOrder", &[0]);
    attribute(&mut want, b"pixelAspectRatio", b"float", &[0, 0, 0x80, 0x3f]);
    attribute(&mut want, b"screenWindowCenter", b"v2f", &[0; 8]);
    attribute(&mut want, b"screenWindowWidth", b"float", &[0, 0, 0x80, 0x3f]);
    want.push(0);
    // Two lines of 8 bytes of y and size, then 3 channels x 3 pixels x 4.
    let first = want.len() as u64 + 16;
    want.extend_from_slice(&first.to_le_bytes());
    want.extend_from_slice(&(first + 8 + 36).to_le_bytes());
    for (y, row) in colors.chunks(3).enumerate() {
        want.extend_from_slice(&(y as u32).to_le_bytes());
        want.extend_from_slice(&36u32.to_le_bytes());
        for c in [2, 1, 0] {
            for p in row {
                let v = if p[c].is_nan() { 0.0 } else { p[c] };
                want.extend_from_slice(&v.to_bits().to_le_bytes());
            }
        }
    }
    let got = exr_bytes(&img);
    assert_eq!(got.len(), want.len());
    let first_difference = got.iter().zip(&want).position(|(a, b)| a != b);
    assert_eq!(first_difference, None, "the bytes differ first at {first_difference:?}");
}

//! Sounds made in code: samples written as a WAV file in memory, for
//! Bevy's `AudioSource` (its `wav` decoder, which the `audio` feature
//! turns on). No recorded asset is needed for an effect.

use bevy::audio::AudioSource;

/// The bytes of a mono 16-bit PCM WAV file holding `samples` (each in
/// `[-1, 1]`, clamped; NaN is silence) at `sample_rate` samples a second.
///
/// ```
/// let bytes = bevy_manifold::audio::wav_bytes(&[0.0, 1.0, -1.0], 8000);
/// assert_eq!(&bytes[0..4], b"RIFF");
/// assert_eq!(bytes.len(), 44 + 3 * 2);
/// // The second sample, full scale: 32767, little-endian.
/// assert_eq!(i16::from_le_bytes([bytes[46], bytes[47]]), 32767);
/// ```
#[must_use]
pub fn wav_bytes(samples: &[f32], sample_rate: u32) -> Vec<u8> {
    let data_len = u32::try_from(samples.len() * 2).unwrap_or(u32::MAX - 36);
    let mut out = Vec::with_capacity(44 + samples.len() * 2);
    out.extend_from_slice(b"RIFF");
    out.extend_from_slice(&(36 + data_len).to_le_bytes());
    out.extend_from_slice(b"WAVEfmt ");
    out.extend_from_slice(&16u32.to_le_bytes()); // fmt chunk size
    out.extend_from_slice(&1u16.to_le_bytes()); // PCM
    out.extend_from_slice(&1u16.to_le_bytes()); // mono
    out.extend_from_slice(&sample_rate.to_le_bytes());
    out.extend_from_slice(&(sample_rate * 2).to_le_bytes()); // bytes a second
    out.extend_from_slice(&2u16.to_le_bytes()); // bytes a frame
    out.extend_from_slice(&16u16.to_le_bytes()); // bits a sample
    out.extend_from_slice(b"data");
    out.extend_from_slice(&data_len.to_le_bytes());
    for &s in samples.iter().take(data_len as usize / 2) {
        let s = if s.is_nan() { 0.0 } else { s.clamp(-1.0, 1.0) };
        out.extend_from_slice(&((s * 32767.0).round() as i16).to_le_bytes());
    }
    out
}

/// [`wav_bytes`] as a Bevy `AudioSource`, ready for `Assets::add`.
#[must_use]
pub fn wav_source(samples: &[f32], sample_rate: u32) -> AudioSource {
    AudioSource {
        bytes: wav_bytes(samples, sample_rate).into(),
    }
}

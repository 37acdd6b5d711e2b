//! The text files users bring (space, generator, scene, tour and settings
//! files) as editors write them: a UTF-8 byte-order mark, which Windows
//! editors put first, is not part of the text ([`without_bom`]); Windows
//! line ends (CRLF) are whitespace to JSON and are split off by
//! `str::lines` in the `.gen` reader.

/// `text` without a leading UTF-8 byte-order mark (U+FEFF).
///
/// ```
/// use bevy_manifold_core::text::without_bom;
/// assert_eq!(without_bom("\u{feff}# a comment"), "# a comment");
/// assert_eq!(without_bom("# a comment"), "# a comment");
/// ```
#[must_use]
pub fn without_bom(text: &str) -> &str {
    text.strip_prefix('\u{feff}').unwrap_or(text)
}

/// The text of the file at `path`, refused unread when it is larger than
/// `max_bytes` (memory stays bounded whatever file is given).
///
/// # Errors
/// The file cannot be read, is not UTF-8, or is too large (the message
/// says its size and the cap).
///
/// ```
/// let dir = std::env::temp_dir().join("bevy_manifold_read_capped_doc");
/// std::fs::create_dir_all(&dir).unwrap();
/// let f = dir.join("t.json");
/// std::fs::write(&f, "0123456789").unwrap();
/// assert_eq!(bevy_manifold_core::text::read_capped(&f, 10).unwrap(), "0123456789");
/// assert!(bevy_manifold_core::text::read_capped(&f, 9).unwrap_err().contains("10 bytes, more than the 9"));
/// ```
pub fn read_capped(path: &std::path::Path, max_bytes: u64) -> Result<String, String> {
    use std::io::Read;
    let file = std::fs::File::open(path).map_err(|e| e.to_string())?;
    let mut text = String::new();
    // One byte past the cap tells a file that is too large, without
    // reading the rest of it.
    let read = file
        .take(max_bytes + 1)
        .read_to_string(&mut text)
        .map_err(|e| e.to_string())?;
    if read as u64 > max_bytes {
        let size = std::fs::metadata(path).map_or(read as u64, |m| m.len());
        return Err(format!("{size} bytes, more than the {max_bytes} this file may have"));
    }
    Ok(text)
}

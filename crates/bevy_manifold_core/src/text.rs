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

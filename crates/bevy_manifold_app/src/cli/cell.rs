//! `space cell`: the cell reached by crossing faces in order from the
//! origin copy, with its id and group element, for a person or a script.

use bevy_manifold::prelude::*;
use bevy_manifold::space::element::CellElement;
use std::io::{BufRead, Write};
use std::path::Path;

/// Most faces in one word (one exact product each).
pub const MAX_WORD: usize = 1 << 20;

/// Parses one comma-separated word of face indices; `what` names where it
/// came from in errors.
fn parse_word(space: &Space, text: &str, what: &str) -> Result<Vec<usize>, String> {
    let text = text.trim();
    if text.is_empty() {
        return Ok(Vec::new());
    }
    let n = space.faces().len();
    let mut word = Vec::new();
    for (i, part) in text.split(',').enumerate() {
        if word.len() >= MAX_WORD {
            return Err(format!("{what}: more than {MAX_WORD} faces"));
        }
        let f: usize = part
            .trim()
            .parse()
            .map_err(|_| format!("{what}: face {i} is '{}', not a face index", part.trim()))?;
        if f >= n {
            return Err(format!(
                "{what}: face {i} is {f}, but the space has {n} faces (0 to {})",
                n - 1
            ));
        }
        word.push(f);
    }
    Ok(word)
}

/// The cell of `word` as one JSON object: `id` (the `u64`), `id_hex`,
/// `scheme`, `exact` (the id is the element's alone), `far`, `faces`
/// (the word's length), `element` (the group element rounded to `f64`,
/// rows), and for exact cells `centre`: the exact image of the domain's
/// centre, `[a, b]` per coordinate for `(a + b phi) / 2^shift`.
fn cell_json(space: &Space, word: &[usize]) -> serde_json::Value {
    let cell = space.cell_of_word(word);
    let id = space.cell_id_of(&cell);
    let m = space.cell_matrix(&cell);
    let rows: Vec<[f64; 4]> = (0..4).map(|i| m.row(i).to_array()).collect();
    let mut out = serde_json::json!({
        "id": id.0,
        "id_hex": format!("{:016x}", id.0),
        "scheme": space.cells().kind(),
        "exact": !id.is_far() && !matches!(space.cells(), bevy_manifold::space::cells::CellScheme::Hashed { .. }),
        "far": id.is_far(),
        "faces": word.len(),
        "element": rows,
    });
    if let CellElement::Exact(e) = &cell {
        let (centre, shift) = e.centre();
        let text = |b: &bevy_manifold::space::exact::int::BigInt| big_decimal(b);
        out["centre"] = serde_json::json!(centre.iter().map(|(a, b)| [text(a), text(b)]).collect::<Vec<_>>());
        out["shift"] = serde_json::json!(shift);
    }
    out
}

/// A big integer in decimal.
fn big_decimal(b: &bevy_manifold::space::exact::int::BigInt) -> String {
    if let Some(x) = b.to_i128() {
        return x.to_string();
    }
    let (negative, limbs) = b.parts();
    let mut limbs = limbs.to_vec();
    let mut digits = Vec::new();
    while !limbs.is_empty() {
        let mut rem = 0u64;
        for l in limbs.iter_mut().rev() {
            let cur = (rem << 32) | u64::from(*l);
            *l = (cur / 1_000_000_000) as u32;
            rem = cur % 1_000_000_000;
        }
        while limbs.last() == Some(&0) {
            limbs.pop();
        }
        digits.push(rem);
    }
    let mut s = String::from(if negative { "-" } else { "" });
    for (i, d) in digits.iter().rev().enumerate() {
        if i == 0 {
            s += &d.to_string();
        } else {
            s += &format!("{d:09}");
        }
    }
    s
}

/// `space cell SPACE --faces ... [--json]` and `--words FILE`.
pub fn cell(space: &Space, faces: Option<&str>, json: bool, words: Option<&Path>) -> Result<(), String> {
    let stdout = std::io::stdout();
    let mut out = stdout.lock();
    let io = |e: std::io::Error| format!("writing the output: {e}");
    if let Some(path) = words {
        let file = std::fs::File::open(path).map_err(|e| format!("{}: {e}", path.display()))?;
        for (k, line) in std::io::BufReader::new(file).lines().enumerate() {
            let line = line.map_err(|e| format!("{}: line {}: {e}", path.display(), k + 1))?;
            let word = parse_word(space, &line, &format!("{} line {}", path.display(), k + 1))?;
            writeln!(out, "{}", cell_json(space, &word)).map_err(io)?;
        }
        return Ok(());
    }
    let word = parse_word(space, faces.unwrap_or(""), "--faces")?;
    let v = cell_json(space, &word);
    if json {
        writeln!(out, "{v}").map_err(io)?;
        return Ok(());
    }
    let exactness = if v["exact"] == true {
        "exact: the same for every path to the cell"
    } else if v["far"] == true {
        "far: best effort beyond the precision horizon"
    } else {
        "rounded centre, path-independent near the origin copy"
    };
    writeln!(out, "space:   {}", space.name()).map_err(io)?;
    writeln!(out, "faces:   {} crossed", word.len()).map_err(io)?;
    writeln!(
        out,
        "id:      {} ({}; {exactness})",
        v["id_hex"].as_str().unwrap_or(""),
        v["scheme"].as_str().unwrap_or("")
    )
    .map_err(io)?;
    writeln!(out, "element (rounded):").map_err(io)?;
    for row in v["element"].as_array().into_iter().flatten() {
        let r: Vec<String> = row
            .as_array()
            .into_iter()
            .flatten()
            .map(|x| format!("{:>14.6e}", x.as_f64().unwrap_or(f64::NAN)))
            .collect();
        writeln!(out, "  {}", r.join(" ")).map_err(io)?;
    }
    if let Some(c) = v["centre"].as_array() {
        writeln!(out, "centre (exact, (a + b phi) / 2^{}):", v["shift"]).map_err(io)?;
        for (axis, ab) in ["x", "y", "z", "w'"].iter().zip(c) {
            writeln!(
                out,
                "  {axis:<2} a = {}, b = {}",
                ab[0].as_str().unwrap_or(""),
                ab[1].as_str().unwrap_or("")
            )
            .map_err(io)?;
        }
    }
    Ok(())
}

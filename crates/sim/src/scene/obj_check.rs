//! What tobj leaves unchecked or unplaced, checked before it reads a file: text that is not
//! UTF-8, vertex lines without their numbers, face indices that are not integers or name no
//! vertex (tobj overflows on huge ones), colour lines of a material library with fewer than
//! three numbers (tobj panics on them). Errors name the line.

/// Checks an OBJ file's text: every line UTF-8; `v` with 3 numbers, `vt` with 2, `vn` with 3;
/// every face (`f`) and line (`l`) index a non-zero integer naming a vertex, texture
/// coordinate or normal of the file (negative: counted back from the last one defined).
pub(crate) fn check_obj(bytes: &[u8]) -> Result<(), String> {
    // Positive indices may name an element defined further down (tobj resolves them when the
    // object ends), so they are checked against the file's totals.
    let mut total = [0usize; 3];
    for line in bytes.split(|&b| b == b'\n') {
        let line = String::from_utf8_lossy(line);
        match line.split_whitespace().next() {
            Some("v") => total[0] += 1,
            Some("vt") => total[1] += 1,
            Some("vn") => total[2] += 1,
            _ => {}
        }
    }
    let mut seen = [0usize; 3];
    for (i, line) in bytes.split(|&b| b == b'\n').enumerate() {
        let n = i + 1;
        let line = std::str::from_utf8(line).map_err(|e| format!("line {n}: not UTF-8 text (byte {} of the line)", e.valid_up_to()))?;
        let mut words = line.split_whitespace();
        let numbers = |words: std::str::SplitWhitespace, need: usize, what: &str| -> Result<(), String> {
            let got: Vec<&str> = words.take(need).collect();
            if got.len() < need || got.iter().any(|w| w.parse::<f32>().is_err()) {
                return Err(format!("line {n}: {what} needs {need} numbers, got \"{}\"", got.join(" ")));
            }
            Ok(())
        };
        match words.next() {
            Some("v") => {
                numbers(words, 3, "a vertex (v)")?;
                seen[0] += 1;
            }
            Some("vt") => {
                numbers(words, 2, "a texture coordinate (vt)")?;
                seen[1] += 1;
            }
            Some("vn") => {
                numbers(words, 3, "a normal (vn)")?;
                seen[2] += 1;
            }
            Some(kind @ ("f" | "l")) => {
                for word in words {
                    let parts: Vec<&str> = word.split('/').collect();
                    if parts.len() > 3 {
                        return Err(format!("line {n}: {kind} element \"{word}\" has more than 3 indices"));
                    }
                    for (k, part) in parts.iter().enumerate().filter(|(_, p)| !p.is_empty()) {
                        let what = ["vertex", "texture coordinate", "normal"][k];
                        let x: i64 = part.parse().map_err(|_| format!("line {n}: {what} index \"{part}\" is not an integer"))?;
                        let ok = if x > 0 { x as u64 <= total[k] as u64 } else { x != 0 && x.unsigned_abs() <= seen[k] as u64 };
                        if !ok {
                            return Err(format!(
                                "line {n}: {what} index {x} is out of range ({} defined{})",
                                if x > 0 { total[k] } else { seen[k] },
                                if x > 0 { "" } else { " so far" }
                            ));
                        }
                    }
                }
            }
            _ => {}
        }
    }
    Ok(())
}

/// Checks a material library's text: every line UTF-8, and the colours `Ka`, `Kd`, `Ks`, `Ke`
/// with 3 numbers.
pub(crate) fn check_mtl(bytes: &[u8]) -> Result<(), String> {
    for (i, line) in bytes.split(|&b| b == b'\n').enumerate() {
        let n = i + 1;
        let line = std::str::from_utf8(line).map_err(|e| format!("line {n}: not UTF-8 text (byte {} of the line)", e.valid_up_to()))?;
        let mut words = line.split_whitespace();
        if let Some(key @ ("Ka" | "Kd" | "Ks" | "Ke")) = words.next() {
            let got: Vec<&str> = words.take(3).collect();
            if got.len() < 3 || got.iter().any(|w| w.parse::<f32>().is_err()) {
                return Err(format!("line {n}: {key} needs 3 numbers, got \"{}\"", got.join(" ")));
            }
        }
    }
    Ok(())
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn obj_lines_are_checked_and_named() {
        let tri = "v 0 0 0\nv 1 0 0\nv 0 1 0\n";
        assert_eq!(check_obj(format!("{tri}vt 0 0\nf 1/1 2/1 -1/-1\nl 1 2\n").as_bytes()), Ok(()));
        // Forward references resolve at the end of the object, as tobj does.
        assert_eq!(check_obj(b"f 1 2 3\nv 0 0 0\nv 1 0 0\nv 0 1 0\n"), Ok(()));
        for (text, want) in [
            (format!("{tri}f 1 2 9\n"), "line 4: vertex index 9 is out of range (3 defined)"),
            (format!("{tri}f 0 1 2\n"), "line 4: vertex index 0 is out of range"),
            (format!("{tri}f 1 2 -4\n"), "line 4: vertex index -4 is out of range (3 defined so far)"),
            (format!("{tri}f 1 2 x\n"), "line 4: vertex index \"x\" is not an integer"),
            (format!("{tri}vt 0 0\nf 1/1 2/4611686018427387904 3/1\n"), "line 5: texture coordinate index 4611686018427387904 is out of range"),
            (format!("{tri}f 1/1/1/1 2 3\n"), "more than 3 indices"),
            ("v 0 0\n".to_string(), "line 1: a vertex (v) needs 3 numbers, got \"0 0\""),
            ("vt 0 a\n".to_string(), "line 1: a texture coordinate (vt) needs 2 numbers"),
        ] {
            let e = check_obj(text.as_bytes()).unwrap_err();
            assert!(e.contains(want), "{e}");
        }
        assert!(check_obj(b"v 0 0 0\n\xff\n").unwrap_err().starts_with("line 2: not UTF-8"));
    }

    #[test]
    fn mtl_colours_need_three_numbers() {
        assert_eq!(check_mtl(b"newmtl a\nKd 1 0 0\nNs 10\n"), Ok(()));
        assert_eq!(check_mtl(b"newmtl a\nKd 1 0\n").unwrap_err(), "line 2: Kd needs 3 numbers, got \"1 0\"");
        assert!(check_mtl(b"Ka x y z\n").is_err());
    }
}

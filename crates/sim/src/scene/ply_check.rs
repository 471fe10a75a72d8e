//! What ply-rs does not survive, checked in the header before it reads a file: numbers too
//! large for it (it unwraps their parse), elements without properties (it reads nothing for
//! each of their entries, however many are declared) and entry counts the data cannot hold.
//! Errors name the header line.

/// Checks a PLY header: numbers in `format` and `element` lines that fit 64 bits, no element
/// with entries but no properties, and no more entries in all than bytes after `end_header`
/// (every entry of an element with properties takes at least one byte). A header without
/// `end_header` is left to ply-rs to report.
pub(crate) fn check_ply_header(bytes: &[u8]) -> Result<(), String> {
    // (name, count, properties, line) of each element.
    let mut elements: Vec<(String, u64, usize, usize)> = Vec::new();
    let mut at = 0;
    for (i, line) in bytes.split(|&b| b == b'\n').enumerate() {
        let n = i + 1;
        at += line.len() + 1;
        let text = String::from_utf8_lossy(line);
        let words: Vec<&str> = text.split_whitespace().collect();
        match words.first().copied() {
            Some("end_header") => {
                let body = bytes.len().saturating_sub(at) as u64;
                let mut total: u64 = 0;
                for (name, count, props, line) in &elements {
                    if *count > 0 && *props == 0 {
                        return Err(format!("line {line}: element '{name}' has {count} entries but no properties"));
                    }
                    total = total.saturating_add(*count);
                    if total > body {
                        return Err(format!("line {line}: element '{name}' declares {count} entries; the {body} bytes after the header cannot hold them"));
                    }
                }
                return Ok(());
            }
            Some(kind @ ("format" | "element")) => {
                // ply-rs reads every digit run of these lines as a u64, and panics past it.
                for run in text.split(|c: char| !c.is_ascii_digit()).filter(|r| !r.is_empty()) {
                    if run.parse::<u64>().is_err() {
                        return Err(format!("line {n}: the number {run} of the {kind} line is too large"));
                    }
                }
                if kind == "element" {
                    let count = words.get(2).and_then(|w| w.parse::<u64>().ok()).unwrap_or(0);
                    elements.push((words.get(1).unwrap_or(&"").to_string(), count, 0, n));
                }
            }
            Some("property") => {
                if let Some(e) = elements.last_mut() {
                    e.2 += 1;
                }
            }
            _ => {}
        }
    }
    Ok(())
}

#[cfg(test)]
mod tests {
    use super::check_ply_header;

    #[test]
    fn ply_headers_are_checked_by_line() {
        let head = |count: &str| format!("ply\nformat ascii 1.0\nelement vertex {count}\nproperty float x\nend_header\n");
        assert_eq!(check_ply_header(format!("{}0\n1\n", head("2")).as_bytes()), Ok(()));
        let e = check_ply_header(format!("{}0\n", head("99999999999999999999999")).as_bytes()).unwrap_err();
        assert_eq!(e, "line 3: the number 99999999999999999999999 of the element line is too large");
        let e = check_ply_header(format!("{}0\n", head("5")).as_bytes()).unwrap_err();
        assert_eq!(e, "line 3: element 'vertex' declares 5 entries; the 2 bytes after the header cannot hold them");
        let e = check_ply_header(b"ply\nformat binary_little_endian 1.0\nelement vertex 1000000000000\nend_header\n").unwrap_err();
        assert_eq!(e, "line 3: element 'vertex' has 1000000000000 entries but no properties");
        assert!(check_ply_header(b"ply\nformat ascii 18446744073709551616.0\nend_header\n").unwrap_err().starts_with("line 2:"));
    }
}

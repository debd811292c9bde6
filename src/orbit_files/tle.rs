//! Two-line element sets (TLE): files of two-line or three-line (a title line first) sets, in any mix,
//! read into [`Sgp4Object`]s in file order ([`read_tle_file`], [`parse_tle`]); Alpha-5 catalogue
//! numbers (a letter for the first digit, as issued since the five-digit numbers ran out) are read.
//!
//! Each line's checksum (column 69: the sum of the digits of columns 1–68, a minus sign counting 1,
//! mod 10) is checked before anything else, and a bad one is an error naming the file and line. The
//! fields are then parsed by the `sgp4` crate (`sgp4::Elements::from_tle`); its complaints are given
//! with the file and line.
//!
//! A title line is any line that is not a TLE line 1 or 2 before a line 1; a leading `0 ` (the
//! three-line form of the catalogue) is dropped from it. Blank lines are skipped; trailing spaces and
//! carriage returns are dropped.

use std::path::Path;

use super::error::OrbitFileError;
use super::sgp4_object::Sgp4Object;

/// A TLE line's length.
const TLE_LINE_LENGTH: usize = 69;

/// What a TLE line must be, for error messages.
const TLE_LINE_ALLOWED: &str =
    "a TLE line of 69 characters, line 1 starting `1 ` and line 2 starting `2 ` (CelesTrak / \
     Space-Track format, Alpha-5 catalogue numbers allowed)";

/// The element sets of a TLE file, in file order.
pub fn read_tle_file(path: &Path) -> Result<Vec<Sgp4Object>, OrbitFileError> {
    let text = super::read_text(path)?;
    parse_tle(&text, &path.display().to_string())
}

/// The element sets of TLE text; `file` names it in errors.
pub fn parse_tle(text: &str, file: &str) -> Result<Vec<Sgp4Object>, OrbitFileError> {
    let lines: Vec<(usize, &str)> = text
        .lines()
        .enumerate()
        .map(|(i, l)| (i + 1, l.trim_end()))
        .filter(|(_, l)| !l.is_empty())
        .collect();
    let mut sets = Vec::new();
    let mut i = 0;
    while i < lines.len() {
        let (number, line) = lines[i];
        let (name, first) = if line.starts_with("1 ") {
            (None, i)
        } else if line.starts_with("2 ") {
            return Err(OrbitFileError::invalid(
                file,
                Some(number),
                "TLE line 2",
                line,
                "a line 2 without a line 1 before it",
                TLE_LINE_ALLOWED,
            ));
        } else {
            let title = line.strip_prefix("0 ").unwrap_or(line).trim();
            (Some(title), i + 1)
        };
        let Some(&(n1, l1)) = lines.get(first) else {
            return Err(OrbitFileError::invalid(
                file,
                Some(number),
                "TLE title line",
                line,
                "the file ends after a title line",
                "a title line followed by TLE lines 1 and 2",
            ));
        };
        let Some(&(_, l2)) = lines.get(first + 1) else {
            return Err(OrbitFileError::invalid(
                file,
                Some(n1),
                "TLE line 1",
                l1,
                "the file ends after line 1",
                "TLE line 1 followed by line 2",
            ));
        };
        sets.push(element_set(file, Some(n1), name, l1, l2)?);
        i = first + 2;
    }
    if sets.is_empty() {
        return Err(OrbitFileError::no_element_set(
            file,
            "one or more two-line or three-line element sets",
        ));
    }
    Ok(sets)
}

/// The checksum of a TLE line's first 68 columns.
fn checksum(line: &str) -> u8 {
    let sum: u32 = line
        .bytes()
        .take(TLE_LINE_LENGTH - 1)
        .map(|b| match b {
            b'0'..=b'9' => u32::from(b - b'0'),
            b'-' => 1,
            _ => 0,
        })
        .sum();
    (sum % 10) as u8
}

/// One element set from its two lines: `line` is the file line of line 1 (`None` for lines given
/// inline, then `source` alone names them).
pub(crate) fn element_set(
    source: &str,
    line: Option<usize>,
    name: Option<&str>,
    line1: &str,
    line2: &str,
) -> Result<Sgp4Object, OrbitFileError> {
    let line1 = line1.trim_end();
    let line2 = line2.trim_end();
    for (k, text) in [(1u8, line1), (2u8, line2)] {
        let at = line.map(|l| l + usize::from(k) - 1);
        let prefix = if k == 1 { "1 " } else { "2 " };
        if text.len() != TLE_LINE_LENGTH || !text.is_ascii() || !text.starts_with(prefix) {
            return Err(OrbitFileError::invalid(
                source,
                at,
                &format!("TLE line {k}"),
                text,
                format!(
                    "{} characters{}",
                    text.chars().count(),
                    if text.starts_with(prefix) {
                        ""
                    } else {
                        ", or the wrong first column"
                    }
                ),
                TLE_LINE_ALLOWED,
            ));
        }
        let found = text.as_bytes()[TLE_LINE_LENGTH - 1] as char;
        let computed = checksum(text);
        if found.to_digit(10) != Some(u32::from(computed)) {
            return Err(OrbitFileError::Checksum {
                file: source.to_string(),
                line: at.unwrap_or(usize::from(k)),
                tle_line: k,
                found,
                computed,
            });
        }
    }
    let elements =
        sgp4::Elements::from_tle(name.map(str::to_string), line1.as_bytes(), line2.as_bytes())
            .map_err(|e| {
                OrbitFileError::invalid(source, line, "TLE", line1, e.to_string(), TLE_LINE_ALLOWED)
            })?;
    let at = match line {
        Some(l) => format!("{source} line {l}"),
        None => source.to_string(),
    };
    Sgp4Object::from_elements(at, elements)
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Vallado's SGP4-VER.TLE satellite 00005 (AIAA 2006-6753).
    const L1: &str = "1 00005U 58002B   00179.78495062  .00000023  00000-0  28098-4 0  4753";
    const L2: &str = "2 00005  34.2682 348.7242 1859667 331.7664  19.3264 10.82419157413667";

    #[test]
    fn reads_two_and_three_line_sets() {
        let text = format!("{L1}\n{L2}\n\nVANGUARD 1\n{L1}\n{L2}\n0 VANGUARD 1\n{L1}\r\n{L2}   \n");
        let sets = parse_tle(&text, "x.tle").unwrap();
        assert_eq!(sets.len(), 3);
        assert_eq!(sets[0].name(), None);
        assert_eq!(sets[1].name(), Some("VANGUARD 1"));
        assert_eq!(sets[2].name(), Some("VANGUARD 1"));
        assert_eq!(sets[2].source(), "x.tle line 8");
        assert!(sets.iter().all(|s| s.norad_id() == 5));
    }

    #[test]
    fn a_bad_checksum_names_the_file_and_line() {
        let bad = format!("{}2", &L2[..68]);
        let err = parse_tle(&format!("SAT\n{L1}\n{bad}\n"), "flock.tle").unwrap_err();
        let text = err.to_string();
        assert!(
            matches!(
                err,
                OrbitFileError::Checksum {
                    line: 3,
                    tle_line: 2,
                    found: '2',
                    computed: 7,
                    ..
                }
            ),
            "{text}"
        );
        assert!(
            text.starts_with("flock.tle line 3: TLE line 2 has checksum 2"),
            "{text}"
        );
    }

    #[test]
    fn malformed_files_are_refused() {
        let short = parse_tle(&format!("{}\n{L2}\n", &L1[..60]), "a.tle").unwrap_err();
        assert!(short.to_string().contains("a.tle line 1"), "{short}");
        let orphan = parse_tle(&format!("{L2}\n"), "b.tle").unwrap_err();
        assert!(orphan.to_string().contains("without a line 1"), "{orphan}");
        let cut = parse_tle(&format!("SAT\n{L1}\n"), "c.tle").unwrap_err();
        assert!(cut.to_string().contains("ends after line 1"), "{cut}");
        assert!(parse_tle("\n\n", "d.tle").is_err());
    }

    /// An Alpha-5 number: `A0001` is 100001 (the letter A stands for 10, I and O are skipped).
    #[test]
    fn reads_alpha_5_numbers() {
        let fix = |line: &str| {
            let body = format!("{}A0001{}", &line[..2], &line[7..68]);
            format!("{body}{}", checksum(&body))
        };
        let sets = parse_tle(&format!("{}\n{}\n", fix(L1), fix(L2)), "a5.tle").unwrap();
        assert_eq!(sets[0].norad_id(), 100_001);
    }
}

//! The lines of a CCSDS keyword = value notation (KVN) message, shared by the OEM and OMM readers:
//! blank lines, `COMMENT` lines, `KEYWORD = value` lines (a trailing unit in brackets, `[km]`,
//! dropped) and anything else (an OEM data line or a block keyword such as `META_START`).

/// One classified line of a KVN message.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub(crate) enum Kvn<'a> {
    /// Empty or only spaces.
    Blank,
    /// `COMMENT …`.
    Comment,
    /// `KEYWORD = value`, both trimmed, the value without a trailing `[unit]`.
    Pair(&'a str, &'a str),
    /// Any other line, trimmed.
    Other(&'a str),
}

/// The lines of `text`, numbered from 1, classified.
pub(crate) fn lines(text: &str) -> impl Iterator<Item = (usize, Kvn<'_>)> {
    text.lines()
        .enumerate()
        .map(|(i, raw)| (i + 1, classify(raw)))
}

fn classify(raw: &str) -> Kvn<'_> {
    let line = raw.trim();
    if line.is_empty() {
        return Kvn::Blank;
    }
    if line == "COMMENT" || line.starts_with("COMMENT ") || line.starts_with("COMMENT\t") {
        return Kvn::Comment;
    }
    match line.split_once('=') {
        Some((key, value)) if is_keyword(key.trim()) => {
            let value = value.trim();
            let value = match value.rfind('[') {
                Some(open) if value.ends_with(']') => value[..open].trim_end(),
                _ => value,
            };
            Kvn::Pair(key.trim(), value)
        }
        _ => Kvn::Other(line),
    }
}

/// A KVN keyword: upper-case letters, digits and underscores, starting with a letter.
fn is_keyword(key: &str) -> bool {
    key.starts_with(|c: char| c.is_ascii_uppercase())
        && key
            .chars()
            .all(|c| c.is_ascii_uppercase() || c.is_ascii_digit() || c == '_')
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn classifies_lines() {
        let text = "CCSDS_OEM_VERS = 2.0\n\nCOMMENT a = b\nX = 1.5 [km]\nMETA_START\n2020-01-01T00:00:00 1 2 3 4 5 6\n";
        let got: Vec<_> = lines(text).map(|(_, k)| k).collect();
        assert_eq!(
            got,
            vec![
                Kvn::Pair("CCSDS_OEM_VERS", "2.0"),
                Kvn::Blank,
                Kvn::Comment,
                Kvn::Pair("X", "1.5"),
                Kvn::Other("META_START"),
                Kvn::Other("2020-01-01T00:00:00 1 2 3 4 5 6"),
            ]
        );
    }
}

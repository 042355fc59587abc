//! Splitting a sentence's text at an ASCII delimiter (`,`, `*`, `.`),
//! byte by byte.
//!
//! `str::split` and `str::split_once` with a `char` go through core's
//! general character searcher, which the optimiser does not always inline
//! and which carries a bounds check (a panic path) of its own. An ASCII
//! byte always sits on a character boundary, so the parts found here are
//! taken with `str::get` (no panic path) and are exactly those of
//! `split(char)`.
//!
//! Used by the field-text rules' reference pass in the tests
//! (`plausible::reference`); the reader splits its bytes itself.

/// The text before the first `delim` and the text after it; `None` when
/// there is none.
pub(crate) fn split_once_ascii(text: &str, delim: u8) -> Option<(&str, &str)> {
    let at = text.bytes().position(|b| b == delim)?;
    // `at` < text.len(): `at + 1` cannot overflow.
    Some((text.get(..at)?, text.get(at + 1..)?))
}

/// The text before the first `delim`, or all of it.
pub(crate) fn before_ascii(text: &str, delim: u8) -> &str {
    split_once_ascii(text, delim).map_or(text, |(head, _)| head)
}

/// `text` without one leading `-` or `+`, and whether that was a `-`:
/// what `strip_prefix(['-', '+'])` gives (the reference pass's twin of the
/// reader's byte-slice `split_sign` in `parse.rs`).
pub(crate) fn split_sign(text: &str) -> (bool, &str) {
    match text.as_bytes().first() {
        // An ASCII sign is one byte: 1 is a character boundary.
        Some(&sign @ (b'-' | b'+')) => (sign == b'-', text.get(1..).unwrap_or(text)),
        _ => (false, text),
    }
}

/// The parts of `text` between `delim`s, as `text.split(delim as char)`
/// gives them (an empty text is one empty part).
pub(crate) fn split_ascii(text: &str, delim: u8) -> SplitAscii<'_> {
    SplitAscii {
        rest: Some(text),
        delim,
    }
}

/// Iterator of [`split_ascii`].
pub(crate) struct SplitAscii<'a> {
    rest: Option<&'a str>,
    delim: u8,
}

impl<'a> Iterator for SplitAscii<'a> {
    type Item = &'a str;

    fn next(&mut self) -> Option<&'a str> {
        let text = self.rest?;
        match split_once_ascii(text, self.delim) {
            Some((part, rest)) => {
                self.rest = Some(rest);
                Some(part)
            }
            None => {
                self.rest = None;
                Some(text)
            }
        }
    }
}

#[cfg(test)]
mod tests {
    extern crate std;
    use std::vec::Vec;

    use super::*;

    const TEXTS: [&str; 9] = [
        "",
        ",",
        ",,",
        "GPGGA,123519,4807.038,N,01131.000,E,1,08,0.9,545.4,M,46.9,M,,",
        "a*b*c",
        "12.50",
        "1.",
        ".5",
        "°,é,",
    ];

    #[test]
    fn parts_are_those_of_str_split() {
        for text in TEXTS {
            for delim in [b',', b'*', b'.'] {
                let ours: Vec<&str> = split_ascii(text, delim).collect();
                let core: Vec<&str> = text.split(char::from(delim)).collect();
                assert_eq!(ours, core, "{text:?} at {:?}", char::from(delim));
                assert_eq!(
                    split_once_ascii(text, delim),
                    text.split_once(char::from(delim)),
                    "{text:?}"
                );
                assert_eq!(before_ascii(text, delim), core[0], "{text:?}");
            }
        }
        for text in TEXTS
            .iter()
            .copied()
            .chain(["-", "+", "-1.5", "+-2", "--", "−3"])
        {
            let core = text.strip_prefix(['-', '+']).unwrap_or(text);
            assert_eq!(split_sign(text), (text.starts_with('-'), core), "{text:?}");
        }
    }
}

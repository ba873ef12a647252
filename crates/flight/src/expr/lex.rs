//! Text → tokens, each with its 1-based column (in characters).

use super::error::{ParseError, Problem};

/// What a token is.
#[derive(Clone, Debug, PartialEq)]
pub enum Tok<'a> {
    /// A finite number.
    Num(f64),
    /// A name: `[A-Za-z_][A-Za-z0-9_]*`.
    Ident(&'a str),
    /// One of `+ - * / ^`.
    Op(char),
    /// `(`.
    Open,
    /// `)`.
    Close,
    /// `,`.
    Comma,
    /// The end of the text.
    End,
}

/// A token and the column it begins at.
#[derive(Clone, Debug, PartialEq)]
pub struct Token<'a> {
    /// What it is.
    pub tok: Tok<'a>,
    /// Its text (empty for [`Tok::End`]).
    pub text: &'a str,
    /// The 1-based column of its first character.
    pub column: usize,
}

/// The tokens of `src`, ending with [`Tok::End`]; columns start at `offset + 1`.
pub fn tokens(src: &str, offset: usize) -> Result<Vec<Token<'_>>, ParseError> {
    let mut out = Vec::new();
    let mut chars = src.char_indices().peekable();
    let mut column = offset;
    let bytes = src.as_bytes();
    while let Some((start, c)) = chars.next() {
        column += 1;
        let here = column;
        let single = |tok| Token {
            tok,
            text: &src[start..start + c.len_utf8()],
            column: here,
        };
        match c {
            c if c.is_whitespace() => continue,
            '+' | '-' | '*' | '/' | '^' => out.push(single(Tok::Op(c))),
            '(' => out.push(single(Tok::Open)),
            ')' => out.push(single(Tok::Close)),
            ',' => out.push(single(Tok::Comma)),
            '0'..='9' | '.' => {
                // Mantissa: digits and points (a second point makes the number malformed, and
                // is reported as such); an exponent only with its digits.
                let mut end = start + 1;
                while end < bytes.len() && (bytes[end].is_ascii_digit() || bytes[end] == b'.') {
                    end += 1;
                }
                if end < bytes.len() && (bytes[end] == b'e' || bytes[end] == b'E') {
                    let mut e = end + 1;
                    if e < bytes.len() && (bytes[e] == b'+' || bytes[e] == b'-') {
                        e += 1;
                    }
                    while e < bytes.len() && bytes[e].is_ascii_digit() {
                        e += 1;
                    }
                    // Without digits (`2e`, `2e+`) the number is malformed, not 2 times `e`.
                    end = e;
                }
                let text = &src[start..end];
                let number = text
                    .parse::<f64>()
                    .map_err(|_| err(here, Problem::BadNumber(text.to_string())))?;
                if !number.is_finite() {
                    return Err(err(here, Problem::NonFiniteNumber(text.to_string())));
                }
                for _ in start + 1..end {
                    chars.next();
                }
                column += end - start - 1;
                out.push(Token {
                    tok: Tok::Num(number),
                    text,
                    column: here,
                });
            }
            c if c.is_ascii_alphabetic() || c == '_' => {
                let mut end = start + 1;
                while end < bytes.len()
                    && (bytes[end].is_ascii_alphanumeric() || bytes[end] == b'_')
                {
                    end += 1;
                }
                for _ in start + 1..end {
                    chars.next();
                }
                column += end - start - 1;
                let text = &src[start..end];
                out.push(Token {
                    tok: Tok::Ident(text),
                    text,
                    column: here,
                });
            }
            c => return Err(err(here, Problem::BadChar(c))),
        }
    }
    out.push(Token {
        tok: Tok::End,
        text: "",
        column: column + 1,
    });
    Ok(out)
}

fn err(column: usize, problem: Problem) -> ParseError {
    ParseError { column, problem }
}

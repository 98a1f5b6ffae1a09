//! Tokens: what the [lexer](super::lexer) splits a scene text into, and
//! the positions diagnostics point at.

use core::fmt;

use super::echo::Echo;

/// A position in the source: 1-based line and column (columns count
/// Unicode scalar values, a tab counts as one).
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
pub struct Pos {
    /// 1-based line.
    pub line: u32,
    /// 1-based column.
    pub col: u32,
}

/// What a token is.
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum TokenKind<'src> {
    /// An identifier or keyword, as written.
    Ident(&'src str),
    /// A number literal.
    Number(f64),
    /// A string literal: the raw text between the quotes.
    Str(&'src str),
    /// `{`
    LBrace,
    /// `}`
    RBrace,
    /// `<`
    Lt,
    /// `>`
    Gt,
    /// `(`
    LParen,
    /// `)`
    RParen,
    /// `,`
    Comma,
    /// `;`
    Semi,
    /// `=`
    Eq,
    /// `+`
    Plus,
    /// `-`
    Minus,
    /// `*`
    Star,
    /// `/`
    Slash,
    /// `#` (starts a directive)
    Hash,
    /// Any other character (always an error for the parser).
    Char(char),
    /// End of input.
    Eof,
}

impl fmt::Display for TokenKind<'_> {
    /// Describes the token for "found ..." in messages.
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self {
            TokenKind::Ident(s) => write!(f, "`{}`", Echo(s)),
            TokenKind::Number(v) => write!(f, "number {v}"),
            TokenKind::Str(s) => write!(f, "string \"{}\"", Echo(s)),
            TokenKind::LBrace => f.write_str("`{`"),
            TokenKind::RBrace => f.write_str("`}`"),
            TokenKind::Lt => f.write_str("`<`"),
            TokenKind::Gt => f.write_str("`>`"),
            TokenKind::LParen => f.write_str("`(`"),
            TokenKind::RParen => f.write_str("`)`"),
            TokenKind::Comma => f.write_str("`,`"),
            TokenKind::Semi => f.write_str("`;`"),
            TokenKind::Eq => f.write_str("`=`"),
            TokenKind::Plus => f.write_str("`+`"),
            TokenKind::Minus => f.write_str("`-`"),
            TokenKind::Star => f.write_str("`*`"),
            TokenKind::Slash => f.write_str("`/`"),
            TokenKind::Hash => f.write_str("`#`"),
            TokenKind::Char(c) => write!(f, "character {c:?}"),
            TokenKind::Eof => f.write_str("end of file"),
        }
    }
}

/// A token and where it starts.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Token<'src> {
    /// What it is.
    pub kind: TokenKind<'src>,
    /// Where it starts.
    pub pos: Pos,
}

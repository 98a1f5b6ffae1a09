//! The scene-file lexer: tokens with `line:col` positions over a `&str`.
//!
//! - Identifiers are ASCII `[A-Za-z_][A-Za-z0-9_]*`; keywords are just
//!   identifiers, compared case-insensitively by the parser.
//! - Numbers: `12`, `1.5`, `.5`, `1.`, `1e-3`, `2.5E+4` (no sign: `-` is an
//!   operator). Values are parsed as `f64`; an overflowing literal is an
//!   error.
//! - Strings: `"..."` on one line; `\x` escapes are skipped over when
//!   looking for the closing quote but not decoded (the token borrows the
//!   raw text between the quotes).
//! - Comments: `// ..` to end of line and `/* .. */`, which nest as in
//!   POV-Ray.
//! - A UTF-8 byte-order mark (U+FEFF) at the start of the text is
//!   skipped, as POV-Ray skips it; anywhere else it is a stray character.
//! - Any other character becomes a [`TokenKind::Char`] token for the parser
//!   to reject with a position; the lexer itself never panics and every
//!   call consumes at least one character or reports end of input.

use super::error::{Diagnostic, DiagnosticKind};
pub use super::token::{Pos, Token, TokenKind};

/// Splits a scene text into tokens. Cheap to copy, so the parser can look
/// ahead by cloning.
#[derive(Debug, Clone)]
pub struct Lexer<'src> {
    src: &'src str,
    /// Byte offset of the next unread character.
    off: usize,
    pos: Pos,
}

impl<'src> Lexer<'src> {
    /// A lexer at the start of `src`. A UTF-8 byte-order mark at the very
    /// start is skipped (POV-Ray accepts one); it takes no column.
    pub fn new(src: &'src str) -> Self {
        Lexer {
            src,
            off: if src.starts_with('\u{feff}') {
                '\u{feff}'.len_utf8()
            } else {
                0
            },
            pos: Pos { line: 1, col: 1 },
        }
    }

    /// The position of the next unread character.
    pub fn pos(&self) -> Pos {
        self.pos
    }

    fn peek_char(&self) -> Option<char> {
        self.src.get(self.off..).and_then(|s| s.chars().next())
    }

    fn peek_char2(&self) -> Option<char> {
        let mut it = self.src.get(self.off..)?.chars();
        it.next();
        it.next()
    }

    fn bump(&mut self) -> Option<char> {
        let c = self.peek_char()?;
        self.off += c.len_utf8();
        if c == '\n' {
            self.pos.line = self.pos.line.saturating_add(1);
            self.pos.col = 1;
        } else {
            self.pos.col = self.pos.col.saturating_add(1);
        }
        Some(c)
    }

    /// Skips whitespace and comments. Bound: each iteration consumes at
    /// least one character of the finite input.
    fn skip_trivia(&mut self) -> Result<(), Diagnostic<'src>> {
        loop {
            match (self.peek_char(), self.peek_char2()) {
                (Some(c), _) if c.is_whitespace() => {
                    self.bump();
                }
                (Some('/'), Some('/')) => {
                    while let Some(c) = self.bump() {
                        if c == '\n' {
                            break;
                        }
                    }
                }
                (Some('/'), Some('*')) => {
                    let start = self.pos;
                    self.bump();
                    self.bump();
                    // POV-Ray block comments nest; `depth` counts open ones.
                    let mut depth: usize = 1;
                    while depth > 0 {
                        match (self.peek_char(), self.peek_char2()) {
                            (None, _) => {
                                return Err(Diagnostic::error(
                                    start,
                                    DiagnosticKind::UnterminatedComment,
                                ))
                            }
                            (Some('*'), Some('/')) => {
                                self.bump();
                                self.bump();
                                depth -= 1;
                            }
                            (Some('/'), Some('*')) => {
                                self.bump();
                                self.bump();
                                depth += 1;
                            }
                            _ => {
                                self.bump();
                            }
                        }
                    }
                }
                _ => return Ok(()),
            }
        }
    }

    /// The next token; `Eof` forever at the end.
    pub fn next_token(&mut self) -> Result<Token<'src>, Diagnostic<'src>> {
        self.skip_trivia()?;
        let pos = self.pos;
        let start = self.off;
        let Some(c) = self.bump() else {
            return Ok(Token {
                kind: TokenKind::Eof,
                pos,
            });
        };
        let kind = match c {
            '{' => TokenKind::LBrace,
            '}' => TokenKind::RBrace,
            '<' => TokenKind::Lt,
            '>' => TokenKind::Gt,
            '(' => TokenKind::LParen,
            ')' => TokenKind::RParen,
            ',' => TokenKind::Comma,
            ';' => TokenKind::Semi,
            '=' => TokenKind::Eq,
            '+' => TokenKind::Plus,
            '-' => TokenKind::Minus,
            '*' => TokenKind::Star,
            '/' => TokenKind::Slash,
            '#' => TokenKind::Hash,
            '"' => return self.string(pos),
            c if c.is_ascii_alphabetic() || c == '_' => {
                while matches!(self.peek_char(), Some(c) if c.is_ascii_alphanumeric() || c == '_') {
                    self.bump();
                }
                TokenKind::Ident(self.src.get(start..self.off).unwrap_or(""))
            }
            c if c.is_ascii_digit()
                || (c == '.' && matches!(self.peek_char(), Some(d) if d.is_ascii_digit())) =>
            {
                return self.number(start, pos, c)
            }
            other => TokenKind::Char(other),
        };
        Ok(Token { kind, pos })
    }

    fn string(&mut self, pos: Pos) -> Result<Token<'src>, Diagnostic<'src>> {
        let start = self.off;
        loop {
            match self.peek_char() {
                None | Some('\n') | Some('\r') => {
                    return Err(Diagnostic::error(pos, DiagnosticKind::UnterminatedString))
                }
                Some('"') => {
                    let text = self.src.get(start..self.off).unwrap_or("");
                    self.bump();
                    return Ok(Token {
                        kind: TokenKind::Str(text),
                        pos,
                    });
                }
                Some('\\') => {
                    self.bump();
                    // Skip the escaped character unless it ends the line.
                    if !matches!(self.peek_char(), None | Some('\n') | Some('\r')) {
                        self.bump();
                    }
                }
                Some(_) => {
                    self.bump();
                }
            }
        }
    }

    fn number(
        &mut self,
        start: usize,
        pos: Pos,
        first: char,
    ) -> Result<Token<'src>, Diagnostic<'src>> {
        let mut seen_dot = first == '.';
        loop {
            match self.peek_char() {
                Some(d) if d.is_ascii_digit() => {
                    self.bump();
                }
                Some('.') if !seen_dot => {
                    seen_dot = true;
                    self.bump();
                }
                _ => break,
            }
        }
        // Exponent only if digits follow (`2e` is `2` then identifier `e`).
        if matches!(self.peek_char(), Some('e') | Some('E')) {
            let mut look = self.clone();
            look.bump();
            if matches!(look.peek_char(), Some('+') | Some('-')) {
                look.bump();
            }
            if matches!(look.peek_char(), Some(d) if d.is_ascii_digit()) {
                while matches!(look.peek_char(), Some(d) if d.is_ascii_digit()) {
                    look.bump();
                }
                *self = look;
            }
        }
        let text = self.src.get(start..self.off).unwrap_or("");
        match text.parse::<f64>() {
            Ok(v) if v.is_finite() => Ok(Token {
                kind: TokenKind::Number(v),
                pos,
            }),
            _ => Err(Diagnostic::error(pos, DiagnosticKind::BadNumber(text))),
        }
    }
}

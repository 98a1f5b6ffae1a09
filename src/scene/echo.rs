//! Scene text quoted in messages, cut short and with control characters
//! escaped.

use core::fmt;

/// Text from the input (a name, a file name, a number as written) shown
/// in a message: at most [`Echo::MAX_CHARS`] characters, then `…`, with
/// control characters escaped (`\u{1b}`, `\0`, `\t`), so a huge or
/// hostile input makes a short, inert message.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct Echo<'a>(pub &'a str);

impl Echo<'_> {
    /// Characters shown before the text is cut.
    pub const MAX_CHARS: usize = 80;
}

impl fmt::Display for Echo<'_> {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        use fmt::Write;
        for (i, c) in self.0.chars().enumerate() {
            if i == Self::MAX_CHARS {
                return f.write_char('…');
            }
            if c.is_control() {
                write!(f, "{}", c.escape_debug())?;
            } else {
                f.write_char(c)?;
            }
        }
        Ok(())
    }
}

//! The one place that converts between the core's byte offsets ([`Span`]) and
//! LSP positions (0-based line, UTF-16 code units within the line).
//!
//! Every conversion clamps instead of failing: a client may send a position
//! past the end of a line or of the document (the spec says to use the line's
//! end), or in the middle of a surrogate pair; the core may hand us an offset
//! inside a multi-byte character. None of these may crash the server.

use gloc_engine::Span;
use ropey::Rope;
use tower_lsp_server::ls_types::{Position, Range};

/// The LSP position of a byte offset.
pub fn position_of(rope: &Rope, byte_offset: usize) -> Position {
    let mut byte_offset = byte_offset.min(rope.len_bytes());
    // Between the `\r` and `\n` of a CRLF is no LSP position: use the line end.
    if byte_offset > 0
        && byte_offset < rope.len_bytes()
        && rope.byte(byte_offset) == b'\n'
        && rope.byte(byte_offset - 1) == b'\r'
    {
        byte_offset -= 1;
    }
    // `byte_to_char` rounds down to the character containing the byte.
    let char_index = rope.byte_to_char(byte_offset);
    let line = rope.char_to_line(char_index);
    let line_start_utf16 = rope.char_to_utf16_cu(rope.line_to_char(line));
    let character = rope.char_to_utf16_cu(char_index) - line_start_utf16;
    Position {
        line: to_u32(line),
        character: to_u32(character),
    }
}

/// The byte offset of an LSP position, clamped to the document and to the
/// position's line (never past its line break).
pub fn offset_of(rope: &Rope, position: Position) -> usize {
    char_index_of(rope, position).map_or(rope.len_bytes(), |index| rope.char_to_byte(index))
}

/// The character index of an LSP position (what the rope edits by), clamped
/// like [`offset_of`]. `None` when the line is past the end of the document.
pub fn char_index_of(rope: &Rope, position: Position) -> Option<usize> {
    let line = position.line as usize;
    if line >= rope.len_lines() {
        return None;
    }
    let line_start = rope.line_to_char(line);
    let line_end = line_start + line_length_without_break(rope, line);
    let line_start_utf16 = rope.char_to_utf16_cu(line_start);
    let line_end_utf16 = rope.char_to_utf16_cu(line_end);
    let wanted_utf16 = (line_start_utf16 + position.character as usize).min(line_end_utf16);
    // Inside a surrogate pair `utf16_cu_to_char` gives the character that
    // contains it, i.e. rounds down: the same rule as for bytes.
    Some(rope.utf16_cu_to_char(wanted_utf16))
}

/// [`position_of`] for many offsets in one pass over the text: walking forward from the
/// last offset costs what lies between them, not a rope look-up. An offset before the
/// last one falls back to `position_of` (and the walk goes on from there).
pub struct PositionWalker<'a> {
    rope: &'a Rope,
    /// The rope's text as one string (the document keeps both).
    text: &'a str,
    /// The last offset converted (on a character boundary, never inside a CRLF), and
    /// its position.
    offset: usize,
    line: u32,
    character: u32,
}

impl<'a> PositionWalker<'a> {
    /// `text` must be `rope`'s contents.
    pub fn new(rope: &'a Rope, text: &'a str) -> PositionWalker<'a> {
        PositionWalker {
            rope,
            text,
            offset: 0,
            line: 0,
            character: 0,
        }
    }

    /// What `position_of(rope, byte_offset)` answers.
    pub fn position(&mut self, byte_offset: usize) -> Position {
        let bytes = self.text.as_bytes();
        if bytes.len() != self.rope.len_bytes() {
            // Not the rope's text after all: be right, if slow.
            return position_of(self.rope, byte_offset);
        }
        let mut target = byte_offset.min(bytes.len());
        // The same adjustments as `position_of`: the line end for the middle of a
        // CRLF, and the start of the character holding the byte.
        if target > 0
            && target < bytes.len()
            && bytes[target] == b'\n'
            && bytes[target - 1] == b'\r'
        {
            target -= 1;
        }
        while !self.text.is_char_boundary(target) {
            target -= 1;
        }
        if target < self.offset {
            let position = position_of(self.rope, target);
            (self.offset, self.line, self.character) = (target, position.line, position.character);
            return position;
        }
        let mut index = self.offset;
        while index < target {
            let byte = bytes[index];
            if byte < 0x80 {
                match byte {
                    b'\n' => (self.line, self.character) = (self.line + 1, 0),
                    // A lone CR breaks the line; in a CRLF the LF does.
                    b'\r' if bytes.get(index + 1) != Some(&b'\n') => {
                        (self.line, self.character) = (self.line + 1, 0);
                    }
                    _ => self.character += 1,
                }
                index += 1;
            } else {
                // A multi-byte character: 4 bytes are a surrogate pair in UTF-16.
                let width = match byte {
                    0xF0.. => 4,
                    0xE0.. => 3,
                    _ => 2,
                };
                self.character += if width == 4 { 2 } else { 1 };
                index += width;
            }
        }
        self.offset = target;
        Position {
            line: self.line,
            character: self.character,
        }
    }
}

/// The LSP range of a span.
pub fn range_of(rope: &Rope, span: Span) -> Range {
    Range {
        start: position_of(rope, span.start as usize),
        end: position_of(rope, span.end as usize),
    }
}

/// The span of an LSP range (start and end clamped; never inverted).
pub fn span_of(rope: &Rope, range: Range) -> Span {
    Span::new(offset_of(rope, range.start), offset_of(rope, range.end))
}

/// Number of characters on a line, not counting its `\n`, `\r\n` or `\r`.
fn line_length_without_break(rope: &Rope, line: usize) -> usize {
    let slice = rope.line(line);
    let mut length = slice.len_chars();
    if length > 0 && slice.char(length - 1) == '\n' {
        length -= 1;
    }
    if length > 0 && slice.char(length - 1) == '\r' {
        length -= 1;
    }
    length
}

fn to_u32(value: usize) -> u32 {
    u32::try_from(value).unwrap_or(u32::MAX)
}

#[cfg(test)]
mod tests {
    use super::*;

    fn pos(line: u32, character: u32) -> Position {
        Position { line, character }
    }

    #[test]
    fn the_walker_answers_what_position_of_answers() {
        let texts = [
            "ab\ncd\n",
            "é𝄞x\n",
            "ab\r\ncd\r\n\r\n",
            "a\rb\r\rc\r",
            "a\u{2028}b\nc",
            "",
            "\n\n",
            "x = \"Ünïcødé 𝄞\" ' ☃\r\nprint 1\rend",
        ];
        for text in texts {
            let rope = Rope::from_str(text);
            let mut walker = PositionWalker::new(&rope, text);
            // Every offset rising (the fast path), including past the end.
            for offset in 0..=text.len() + 2 {
                assert_eq!(
                    walker.position(offset),
                    position_of(&rope, offset),
                    "{text:?} at {offset}"
                );
            }
            // Falling and jumping (the fallback, and walking on from it).
            let mut walker = PositionWalker::new(&rope, text);
            let mut offset = text.len() / 2;
            for step in 0..3 * text.len() + 3 {
                offset = (offset * 7 + step * 3 + 1) % (text.len() + 1);
                assert_eq!(
                    walker.position(offset),
                    position_of(&rope, offset),
                    "{text:?} at {offset}"
                );
            }
        }
    }

    /// Byte offsets and the LSP positions they are at, worked by hand ('é' is 2
    /// bytes and 1 UTF-16 unit, '𝄞' 4 bytes and 2 units), checked both ways.
    #[test]
    fn offsets_and_positions_agree() {
        for (text, offset, (line, character)) in [
            ("ab\ncd\n", 0, (0, 0)),
            ("ab\ncd\n", 4, (1, 1)),
            ("ab\ncd\n", 6, (2, 0)),
            ("é𝄞x\n", 2, (0, 1)),
            ("é𝄞x\n", 6, (0, 3)),
            // A carriage return alone breaks a line.
            ("a\rb", 2, (1, 0)),
            ("a\rb", 3, (1, 1)),
            // U+2028 (3 bytes) is a line break for some tools but not for LSP.
            ("a\u{2028}b\nc", 5, (0, 3)),
        ] {
            let rope = Rope::from_str(text);
            let position = pos(line, character);
            assert_eq!(position_of(&rope, offset), position, "{text:?} at {offset}");
            assert_eq!(
                offset_of(&rope, position),
                offset,
                "{text:?} at {position:?}"
            );
        }
        assert_eq!(Rope::from_str("a\u{2028}b\nc").len_lines(), 2);
    }

    /// An offset or a position inside a character rounds down to its start; one
    /// past the end of its line or of the text is clamped.
    #[test]
    fn places_inside_a_character_or_past_the_end_are_moved_back() {
        for (text, (line, character), offset) in [
            // Inside the surrogate pair: the start of '𝄞'.
            ("é𝄞x\n", (0, 2), 2),
            // Past the end of line 0 stops before "\r\n".
            ("ab\r\ncd", (0, 99), 2),
            ("ab\r\ncd", (1, 99), 6),
            ("ab\r\ncd", (7, 0), 6),
        ] {
            let rope = Rope::from_str(text);
            assert_eq!(offset_of(&rope, pos(line, character)), offset, "{text:?}");
        }
        // Inside 'é'; past the end of the text.
        for (text, offset, position) in [("é𝄞x\n", 1, pos(0, 0)), ("ab\r\ncd", 999, pos(1, 2))]
        {
            assert_eq!(
                position_of(&Rope::from_str(text), offset),
                position,
                "{text:?}"
            );
        }
    }

    #[test]
    fn round_trip_on_every_char_boundary() {
        let text = "label 0\n  loads 444,r0 # ü m_depth ✓\r\n𝄞𝄞\rend";
        let rope = Rope::from_str(text);
        for (offset, _) in text.char_indices().chain([(text.len(), ' ')]) {
            let position = position_of(&rope, offset);
            let back = offset_of(&rope, position);
            // The offset of "\n" in "\r\n" maps to the line end, before "\r".
            if text[..offset].ends_with('\r') && text[offset..].starts_with('\n') {
                assert_eq!(back, offset - 1);
                assert_eq!(position, position_of(&rope, offset - 1));
            } else {
                assert_eq!(back, offset, "offset {offset} → {position:?}");
            }
        }
    }
}

//! The text tables of appcast reports (MOOS-IvP `ACTable`, `lib_apputil`): columns padded to
//! their widest cell, two spaces between columns, optional dashed header lines, long cells
//! cut in the middle.
//!
//! ```
//! use appcast::Table;
//! let mut t = Table::new(3);
//! t.push("Name | Speed | Note");
//! t.add_header_lines();
//! t.push("abe");
//! t.push("1.5");
//! t.push("");
//! let mut s = String::new();
//! t.write(&mut s);
//! assert_eq!(s, "Name  Speed  Note\n----  -----  ----\nabe   1.5");
//! ```

/// A table being filled cell by cell, row after row (cells wrap to the next row after the
/// last column).
#[derive(Debug, Clone)]
pub struct Table {
    columns: usize,
    cells: Vec<String>,
    max_width: Vec<usize>,
    padded: Vec<bool>,
    right: Vec<bool>,
    pads: Vec<String>,
}

/// A cell that stands for a header line of dashes.
const HEADER_CELL: &str = "{}";

impl Table {
    /// An empty table of `columns` columns, two spaces between columns.
    pub fn new(columns: usize) -> Self {
        Self::with_pad(columns, 2)
    }

    /// An empty table of `columns` columns, `pad` spaces after each column (the C++
    /// `ACTable(columns, pad)`).
    pub fn with_pad(columns: usize, pad: usize) -> Self {
        Self {
            columns,
            cells: Vec::new(),
            max_width: vec![0; columns],
            padded: vec![true; columns],
            right: vec![false; columns],
            pads: vec![" ".repeat(pad); columns],
        }
    }

    /// Sets the text written after column `ix` (C++ `setColumnPadStr`).
    pub fn set_column_pad_str(&mut self, ix: usize, pad: &str) {
        if let Some(p) = self.pads.get_mut(ix) {
            *p = pad.to_string();
        }
    }

    /// Justifies column `ix` to the right (`true`) or left (C++ `setColumnJustify`, where
    /// anything but `left` pads on the left).
    pub fn set_right_justify(&mut self, ix: usize, right: bool) {
        if let Some(r) = self.right.get_mut(ix) {
            *r = right;
        }
    }

    /// Cuts the cells of column `ix` to at most `width` characters (and its header line).
    pub fn set_max_width(&mut self, ix: usize, width: usize) {
        if let Some(w) = self.max_width.get_mut(ix) {
            *w = width;
        }
    }

    /// Leaves the cells of column `ix` unpadded (for the last column).
    pub fn set_no_pad(&mut self, ix: usize) {
        if let Some(p) = self.padded.get_mut(ix) {
            *p = false;
        }
    }

    /// A row of dashed header lines, each as wide as its column.
    pub fn add_header_lines(&mut self) {
        for _ in 0..self.columns {
            self.cells.push(HEADER_CELL.into());
        }
    }

    /// Adds cells as the C++ `<<` of a string does: `_ignore_` adds nothing, an empty text
    /// one empty cell, and any other text one cell per `|`-separated part, each trimmed.
    pub fn push(&mut self, text: &str) {
        if text == "_ignore_" {
            return;
        }
        if text.is_empty() {
            self.cells.push(String::new());
            return;
        }
        for part in text.split('|') {
            self.cells.push(part.trim().to_string());
        }
    }

    /// Appends the table, rows separated by newlines (none after the last), trailing blanks
    /// of each row removed.
    pub fn write(&self, out: &mut String) {
        if self.columns == 0 || self.cells.is_empty() {
            return;
        }
        let mut widest = vec![0usize; self.columns];
        for (i, c) in self.cells.iter().enumerate() {
            let j = i % self.columns;
            widest[j] = widest[j].max(c.chars().count());
        }
        let rows = self.cells.len().div_ceil(self.columns);
        for r in 0..rows {
            let row_start = out.len();
            for (j, &widest) in widest.iter().enumerate() {
                let cell = self
                    .cells
                    .get(r * self.columns + j)
                    .map(String::as_str)
                    .unwrap_or("");
                let limit = self.max_width[j];
                let cap = |w: usize| if limit > 0 { w.min(limit) } else { w };
                if cell == HEADER_CELL {
                    out.push_str(&"-".repeat(cap(widest)));
                } else {
                    let cell = if limit > 0 && cell.chars().count() > limit {
                        cut_middle(cell, limit)
                    } else {
                        cell.to_string()
                    };
                    let len = cell.chars().count();
                    let fill = if self.padded[j] && len < widest {
                        " ".repeat(cap(widest).saturating_sub(len))
                    } else {
                        String::new()
                    };
                    if self.right[j] {
                        out.push_str(&fill);
                        out.push_str(&cell);
                    } else {
                        out.push_str(&cell);
                        out.push_str(&fill);
                    }
                }
                if j + 1 < self.columns {
                    out.push_str(&self.pads[j]);
                }
            }
            let keep = out[row_start..].trim_end_matches([' ', '\t']).len();
            out.truncate(row_start + keep);
            if r + 1 < rows {
                out.push('\n');
            }
        }
    }
}

/// MOOS `truncString(s, len, "mid")`: the front, `..`, the back; under 4 characters just the
/// front.
fn cut_middle(s: &str, len: usize) -> String {
    let chars: Vec<char> = s.chars().collect();
    if len >= chars.len() {
        return s.to_string();
    }
    if len < 4 {
        return chars[..len].iter().collect();
    }
    let back = len / 2 - 1;
    let front = len - len / 2 - 1;
    let mut out: String = chars[..front].iter().collect();
    out.push_str("..");
    out.extend(&chars[chars.len() - back..]);
    out
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn long_cells_are_cut_in_the_middle_and_the_last_column_is_not_padded() {
        let mut t = Table::new(2);
        t.push("Var | Value");
        t.add_header_lines();
        t.set_max_width(1, 8);
        t.set_no_pad(1);
        t.push("A");
        t.push("0123456789abc");
        t.push("LONGNAME");
        t.push("x");
        let mut s = String::new();
        t.write(&mut s);
        // Column 1's widest cell is 13 characters: its header line is capped at 8; the cut
        // keeps 3 in front and 3 behind (8/2 - 1 = 3, 8 - 4 - 1 = 3).
        assert_eq!(
            s,
            "Var       Value\n--------  --------\nA         012..abc\nLONGNAME  x"
        );
    }

    #[test]
    fn pads_and_right_justification() {
        let mut t = Table::with_pad(3, 1);
        t.push("A | Bb | C");
        t.set_column_pad_str(0, " | ");
        t.set_right_justify(1, true);
        t.push("xyz");
        t.push("q");
        t.push("w");
        let mut s = String::new();
        t.write(&mut s);
        assert_eq!(s, "A   | Bb C\nxyz |  q w");
    }

    #[test]
    fn cells_follow_the_cpp_stream_rules() {
        let mut t = Table::new(2);
        t.push("_ignore_");
        t.push(" a |b ");
        t.push("");
        t.push("c");
        let mut s = String::new();
        t.write(&mut s);
        assert_eq!(s, "a  b\n   c");
        assert_eq!(cut_middle("abcdef", 3), "abc");
        assert_eq!(cut_middle("abcdefghij", 5), "ab..j");
    }
}

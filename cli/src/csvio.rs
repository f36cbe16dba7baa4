//! CSV input and output for the command-line program, and atomic file
//! writing.
//!
//! * [`CsvReader`] reads a CSV file with a header row one [`Row`] at a
//!   time (so a run over a long record need not hold it in memory), with
//!   exact line numbers; it refuses blank lines before the last row and
//!   duplicate column names; [`read_columns`] parses whole columns as
//!   finite `f64` values, [`read_time_step`] the sample period of a time
//!   column;
//! * [`write_columns`] writes named `f64` columns; every number written is
//!   formatted by [`fmt_f64`] (shortest round-trip text, scientific for
//!   very large and very small magnitudes);
//! * [`write_atomic`] writes any file through a temporary file in the
//!   destination's directory, renamed over the destination only when
//!   complete, so a reader never sees a half-written file and a failed
//!   write leaves no file behind ([`write_atomic_with`] for writers that
//!   fail with their own error).
//!
//! Every error is a [`CsvIoError`] whose message is one line naming the
//! file and, where relevant, the row (1-based data row, and the line in the
//! file) and the column.

use std::fs;
use std::io::{self, BufRead, BufWriter, Write};
use std::path::{Path, PathBuf};

/// An error reading or writing a CSV file (one-line message).
#[derive(Debug, thiserror::Error)]
pub enum CsvIoError {
    /// The file could not be opened or read.
    #[error("`{}`: {}", path.display(), one_line(&source.to_string()))]
    Io {
        /// The file.
        path: PathBuf,
        /// What failed.
        source: io::Error,
    },
    /// The file has no header row.
    #[error("`{}`: empty file (no header row)", path.display())]
    NoHeader {
        /// The file.
        path: PathBuf,
    },
    /// The file has a header but no data rows.
    #[error("`{}`: no data rows after the header", path.display())]
    NoRows {
        /// The file.
        path: PathBuf,
    },
    /// A blank line before the header or between two data rows (blank
    /// lines at the very end of the file are accepted).
    #[error("`{}`, line {line}: blank line {}; blank lines are only accepted at the end of the file", path.display(), blank_place(*before))]
    BlankLine {
        /// The file.
        path: PathBuf,
        /// 1-based line in the file of the (first) blank line.
        line: u64,
        /// The data row after it and that row's line (`None`: the blank
        /// line comes before the header).
        before: Option<(usize, u64)>,
    },
    /// Two header columns have the same name (after trimming spaces).
    #[error("`{}`: column `{column}` appears twice in the header (columns {first} and {second}); column names must be unique", path.display())]
    DuplicateColumn {
        /// The file.
        path: PathBuf,
        /// The repeated name.
        column: String,
        /// 1-based position of its first occurrence.
        first: usize,
        /// 1-based position of the second.
        second: usize,
    },
    /// The requested column is not in the header.
    #[error("`{}`: no column `{column}` in the header (columns: {})", path.display(), available.join(", "))]
    MissingColumn {
        /// The file.
        path: PathBuf,
        /// The requested column.
        column: String,
        /// The columns the header has.
        available: Vec<String>,
    },
    /// A cell is not a number, or not a finite one.
    #[error("`{}`, row {row} (line {line}), column `{column}`: `{value}` is {reason}", path.display())]
    BadCell {
        /// The file.
        path: PathBuf,
        /// 1-based data row (the header is row 0).
        row: usize,
        /// 1-based line in the file.
        line: u64,
        /// The column.
        column: String,
        /// The cell's text.
        value: String,
        /// `"not a number"` or `"not finite"`.
        reason: &'static str,
    },
    /// A time column is not uniformly spaced (or does not increase, or
    /// has fewer than two rows).
    #[error("`{}`, row {row} (line {line}), column `{column}`: {message}", path.display())]
    NotUniform {
        /// The file.
        path: PathBuf,
        /// 1-based data row where the spacing breaks.
        row: usize,
        /// 1-based line in the file of that row.
        line: u64,
        /// The time column.
        column: String,
        /// What is wrong.
        message: String,
    },
    /// The CSV structure is broken (for example a row with a different
    /// number of fields than the header, or invalid UTF-8).
    #[error("`{}`{}: malformed CSV: {}", path.display(), row_line(*row, *line), one_line(message))]
    Malformed {
        /// The file.
        path: PathBuf,
        /// 1-based data row, if known.
        row: Option<usize>,
        /// 1-based line in the file, if known.
        line: Option<u64>,
        /// What is wrong.
        message: String,
    },
}

/// Where a blank line is: `before row r (line l)` or `before the header`.
fn blank_place(before: Option<(usize, u64)>) -> String {
    match before {
        Some((row, line)) => format!("before row {row} (line {line})"),
        None => "before the header".to_string(),
    }
}

/// `, row r (line l)`, `, line l`, `, row r` or nothing.
fn row_line(row: Option<usize>, line: Option<u64>) -> String {
    match (row, line) {
        (Some(r), Some(l)) => format!(", row {r} (line {l})"),
        (None, Some(l)) => format!(", line {l}"),
        (Some(r), None) => format!(", row {r}"),
        (None, None) => String::new(),
    }
}

/// Joins the lines of a message so that every error stays on one line.
pub fn one_line(s: &str) -> String {
    s.split_whitespace().collect::<Vec<_>>().join(" ")
}

/// Several numeric columns of a CSV file, read by [`read_columns`].
#[derive(Debug, Clone, PartialEq)]
pub struct Columns {
    /// Column names, as in the header.
    pub headers: csv::StringRecord,
    /// Index in the header of each requested column.
    pub indices: Vec<usize>,
    /// Each requested column's values, one per data row (all finite).
    pub values: Vec<Vec<f64>>,
    /// 1-based line in the file of each data row (for messages).
    pub lines: Vec<u64>,
}

/// Reads `path` (a CSV file with a header row) and parses each of
/// `columns` (matched after trimming spaces, in that order; a column may be
/// named twice) as finite numbers. A row's cells are checked in the order
/// of `columns`, so the first bad cell of the first bad row is the one
/// reported.
///
/// Errors: everything [`CsvReader`] refuses (unreadable file, no header,
/// duplicate column names, blank lines before the last row, rows with a
/// different number of fields, invalid UTF-8); no such column; no data
/// rows; a cell that is not a number or not finite (`NaN`, `inf`), naming
/// row, line and column.
pub fn read_columns(path: &Path, columns: &[&str]) -> Result<Columns, CsvIoError> {
    let mut reader = CsvReader::open(path)?;
    let indices = columns
        .iter()
        .map(|c| reader.column(c))
        .collect::<Result<Vec<usize>, _>>()?;
    let names: Vec<String> = indices
        .iter()
        .map(|&i| reader.headers()[i].trim().to_string())
        .collect();
    let mut values = vec![Vec::new(); columns.len()];
    let mut lines = Vec::new();
    let mut row = Row::default();
    while reader.read_row(&mut row)? {
        for ((&index, name), column) in indices.iter().zip(&names).zip(&mut values) {
            column.push(reader.number(&row, index, name)?);
        }
        lines.push(row.line());
    }
    if lines.is_empty() {
        return Err(CsvIoError::NoRows {
            path: path.to_path_buf(),
        });
    }
    Ok(Columns {
        headers: reader.headers().clone(),
        indices,
        values,
        lines,
    })
}

/// Largest relative deviation of a time step from the first one that
/// [`read_time_step`] accepts: a thousandth of a step. Measured time stamps
/// are written rounded (`1.000976562` for 1025/1024 s: a step then differs
/// from the next by up to 2e-6 of itself at 9 decimals, 2e-4 at 7); a
/// record whose steps really differ by more is refused. The period used is
/// the mean step, so rounding does not accumulate; a rate-dependent model
/// run on a record whose true steps jitter within the tolerance errs by
/// about that relative amount.
pub const TIME_STEP_REL_TOL: f64 = 1e-3;

/// Reads the time column `column` of `path` (row by row, keeping nothing
/// but the running check) and returns its sample period: the mean step
/// `(t_last − t_first)/(n − 1)`.
///
/// The column must have at least two rows, increase, and be uniformly
/// spaced: every step within [`TIME_STEP_REL_TOL`] (relative) of the first
/// one. Otherwise [`CsvIoError::NotUniform`] names the row where it breaks.
/// The file is checked like [`read_columns`] does.
pub fn read_time_step(path: &Path, column: &str) -> Result<f64, CsvIoError> {
    let mut reader = CsvReader::open(path)?;
    let index = reader.column(column)?;
    let name = reader.headers()[index].trim().to_string();
    let mut check = StepCheck::new(path, &name);
    let mut row = Row::default();
    while reader.read_row(&mut row)? {
        let t = reader.number(&row, index, &name)?;
        check.push(t, row.line())?;
    }
    if check.rows() == 0 {
        return Err(CsvIoError::NoRows {
            path: path.to_path_buf(),
        });
    }
    check.finish()
}

/// The sample period of a time column (see [`read_time_step`]); `lines`
/// are the file lines of its rows.
pub fn uniform_step(
    path: &Path,
    column: &str,
    t: &[f64],
    lines: &[u64],
) -> Result<f64, CsvIoError> {
    let mut check = StepCheck::new(path, column);
    for (i, &ti) in t.iter().enumerate() {
        check.push(ti, lines.get(i).copied().unwrap_or(i as u64 + 2))?;
    }
    check.finish()
}

/// The running check of a time column behind [`read_time_step`] and
/// [`uniform_step`]: fed one stamp at a time, it keeps the first stamp, the
/// first step and the last stamp only.
#[derive(Debug, Clone)]
struct StepCheck {
    path: PathBuf,
    column: String,
    /// Rows seen.
    n: usize,
    /// First stamp and its line.
    first: (f64, u64),
    /// The first step.
    step: f64,
    /// The last stamp.
    last: f64,
}

impl StepCheck {
    fn new(path: &Path, column: &str) -> Self {
        StepCheck {
            path: path.to_path_buf(),
            column: column.to_string(),
            n: 0,
            first: (0.0, 2),
            step: 0.0,
            last: 0.0,
        }
    }

    fn rows(&self) -> usize {
        self.n
    }

    fn err(&self, row: usize, line: u64, message: String) -> CsvIoError {
        CsvIoError::NotUniform {
            path: self.path.clone(),
            row,
            line,
            column: self.column.clone(),
            message,
        }
    }

    /// The next stamp `t`, on file line `line`.
    fn push(&mut self, t: f64, line: u64) -> Result<(), CsvIoError> {
        let i = self.n;
        match i {
            0 => self.first = (t, line),
            1 => {
                let first = t - self.last;
                if !(first > 0.0 && first.is_finite()) {
                    return Err(self.err(
                        2,
                        line,
                        format!(
                            "time does not increase ({} after {})",
                            fmt_f64(t),
                            fmt_f64(self.last)
                        ),
                    ));
                }
                self.step = first;
            }
            _ => {
                let (step, first) = (t - self.last, self.step);
                if (step - first).abs() > TIME_STEP_REL_TOL * first {
                    return Err(self.err(
                        i + 1,
                        line,
                        format!(
                            "time step {} (from {} to {}) differs from the first step {} \
                             by more than {TIME_STEP_REL_TOL:e} relative (more than the rounding of \
                             written time stamps): the time column must be uniformly spaced",
                            fmt_f64(step),
                            fmt_f64(self.last),
                            fmt_f64(t),
                            fmt_f64(first),
                        ),
                    ));
                }
            }
        }
        self.last = t;
        self.n += 1;
        Ok(())
    }

    /// The mean step, or an error for fewer than two rows.
    fn finish(&self) -> Result<f64, CsvIoError> {
        let n = self.n;
        if n < 2 {
            return Err(self.err(
                1,
                self.first.1,
                format!("a time column needs at least 2 rows to give a sample period (got {n})"),
            ));
        }
        Ok((self.last - self.first.0) / (n - 1) as f64)
    }
}

/// One data row read by [`CsvReader::read_row`]: its fields (UTF-8) and
/// where it is in the file. Reused from row to row, so reading a file
/// allocates only for its longest row.
#[derive(Debug, Clone, Default)]
pub struct Row {
    /// The fields, concatenated.
    text: String,
    /// End offset in `text` of each field.
    ends: Vec<usize>,
    /// 1-based data row (the header is row 0).
    row: usize,
    /// 1-based line in the file where the row starts.
    line: u64,
}

impl Row {
    /// 1-based data row (the header is row 0).
    pub fn row(&self) -> usize {
        self.row
    }

    /// 1-based line in the file where the row starts.
    pub fn line(&self) -> u64 {
        self.line
    }

    /// Number of fields.
    pub fn len(&self) -> usize {
        self.ends.len()
    }

    /// True when the row has no fields (never for a row read from a file).
    pub fn is_empty(&self) -> bool {
        self.ends.is_empty()
    }

    /// Field `i` (verbatim, unquoted); panics if `i >= self.len()`.
    pub fn field(&self, i: usize) -> &str {
        let start = if i == 0 { 0 } else { self.ends[i - 1] };
        // every end is a character boundary (checked when the row was read)
        self.text.get(start..self.ends[i]).unwrap_or_default()
    }

    /// The fields in order.
    pub fn fields(&self) -> impl Iterator<Item = &str> + '_ {
        (0..self.len()).map(|i| self.field(i))
    }
}

/// Checks that every field end lies on a character boundary of `text`
/// (the fields without their delimiters, concatenated). A delimiter
/// between the bytes of one multi-byte character leaves each field
/// invalid UTF-8 although their concatenation is valid (`$\xd4,\xab`
/// reads as `$ԫ` once the comma is gone); found by the `csv_read` fuzz
/// target as a slicing panic.
fn split_check(text: &str, ends: &[usize]) -> Result<(), String> {
    match ends.iter().position(|&e| !text.is_char_boundary(e)) {
        None => Ok(()),
        Some(i) => Err(format!(
            "invalid UTF-8 (field {} ends inside a multi-byte character)",
            i + 1
        )),
    }
}

/// Line bookkeeping of [`CsvReader`]: counts lines (`\n`, `\r\n` and a lone
/// `\r` each end one) over the bytes the CSV parser consumes and notes the
/// first blank line skipped before a record.
#[derive(Debug, Clone)]
struct Lines {
    /// 1-based line of the next byte.
    line: u64,
    /// The last byte consumed was `\r` (a `\n` after it ends the same line).
    prev_cr: bool,
    /// No byte of the current record consumed yet (only line ends).
    at_start: bool,
    /// Line where the current record starts.
    record_line: u64,
    /// First blank line skipped before the current record.
    blank: Option<u64>,
}

impl Lines {
    fn new() -> Self {
        Lines {
            line: 1,
            prev_cr: false,
            at_start: true,
            record_line: 1,
            blank: None,
        }
    }

    fn scan(&mut self, bytes: &[u8]) {
        for &b in bytes {
            match b {
                b'\n' if self.prev_cr => self.prev_cr = false,
                b'\n' | b'\r' => {
                    if self.at_start {
                        self.blank.get_or_insert(self.line);
                    }
                    self.line += 1;
                    self.prev_cr = b == b'\r';
                }
                _ => {
                    if self.at_start {
                        self.at_start = false;
                        self.record_line = self.line;
                    }
                    self.prev_cr = false;
                }
            }
        }
    }

    /// A record ended: the next byte starts a new one.
    fn next_record(&mut self) {
        self.at_start = true;
        self.blank = None;
    }
}

/// A CSV file read row by row (comma-separated, `"`-quoted, any of `\n`,
/// `\r\n`, `\r` ending a line; a UTF-8 byte-order mark is skipped).
///
/// Stricter than the `csv` crate's reader, which skips blank lines
/// silently and counts lines off by one in `\r\n` files: a blank line
/// before the header or between two rows is a
/// [`CsvIoError::BlankLine`] naming it (blank lines at the very end of the
/// file, such as a final empty line, are accepted); two header columns of
/// the same name (after trimming spaces) are a
/// [`CsvIoError::DuplicateColumn`]; a row with a different number of fields
/// than the header, or one that is not UTF-8, is
/// [`CsvIoError::Malformed`]. Line numbers are exact: the line where the
/// row starts, counting every line of the file from 1.
pub struct CsvReader {
    path: PathBuf,
    core: csv_core::Reader,
    input: io::BufReader<Box<dyn io::Read>>,
    lines: Lines,
    headers: csv::StringRecord,
    rows: usize,
    /// Parser output buffers (grown as needed).
    out: Vec<u8>,
    ends: Vec<usize>,
}

impl std::fmt::Debug for CsvReader {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.debug_struct("CsvReader")
            .field("path", &self.path)
            .field("headers", &self.headers)
            .field("rows", &self.rows)
            .finish_non_exhaustive()
    }
}

/// Where a raw record read by [`CsvReader`] starts, and the first blank
/// line before it.
struct RawPos {
    line: u64,
    blank: Option<u64>,
}

impl CsvReader {
    /// Opens `path` and reads its header row. A file whose name ends in
    /// `.gz` is read through gzip decompression (flate2), so records may be
    /// kept compressed.
    ///
    /// Errors: the file cannot be read; no header (empty file); a blank
    /// line before the header; two columns of the same name; invalid
    /// UTF-8 in the header.
    pub fn open(path: &Path) -> Result<Self, CsvIoError> {
        let file = fs::File::open(path).map_err(|source| CsvIoError::Io {
            path: path.to_path_buf(),
            source,
        })?;
        let gz = path
            .extension()
            .is_some_and(|e| e.eq_ignore_ascii_case("gz"));
        let file: Box<dyn io::Read> = if gz {
            Box::new(flate2::read::MultiGzDecoder::new(io::BufReader::new(file)))
        } else {
            Box::new(file)
        };
        let mut reader = CsvReader {
            path: path.to_path_buf(),
            core: csv_core::Reader::new(),
            input: io::BufReader::with_capacity(1 << 16, file),
            lines: Lines::new(),
            headers: csv::StringRecord::new(),
            rows: 0,
            out: vec![0; 1024],
            ends: vec![0; 32],
        };
        let no_header = || CsvIoError::NoHeader {
            path: path.to_path_buf(),
        };
        let Some((pos, n, nend)) = reader.read_raw()? else {
            return Err(no_header());
        };
        if let Some(line) = pos.blank {
            return Err(CsvIoError::BlankLine {
                path: path.to_path_buf(),
                line,
                before: None,
            });
        }
        let text = std::str::from_utf8(&reader.out[..n]).map_err(|e| CsvIoError::Malformed {
            path: path.to_path_buf(),
            row: Some(0),
            line: Some(pos.line),
            message: format!("invalid UTF-8 in the header ({e})"),
        })?;
        split_check(text, &reader.ends[..nend]).map_err(|message| CsvIoError::Malformed {
            path: path.to_path_buf(),
            row: Some(0),
            line: Some(pos.line),
            message: format!("{message} in the header"),
        })?;
        let mut headers = csv::StringRecord::new();
        let mut start = 0;
        for &end in &reader.ends[..nend] {
            headers.push_field(text.get(start..end).unwrap_or_default());
            start = end;
        }
        if headers.is_empty() || (headers.len() == 1 && headers[0].trim().is_empty()) {
            return Err(no_header());
        }
        for (j, name) in headers.iter().enumerate() {
            if let Some(i) = headers.iter().take(j).position(|h| h.trim() == name.trim()) {
                return Err(CsvIoError::DuplicateColumn {
                    path: path.to_path_buf(),
                    column: name.trim().to_string(),
                    first: i + 1,
                    second: j + 1,
                });
            }
        }
        reader.headers = headers;
        Ok(reader)
    }

    /// The file.
    pub fn path(&self) -> &Path {
        &self.path
    }

    /// The header's column names, verbatim.
    pub fn headers(&self) -> &csv::StringRecord {
        &self.headers
    }

    /// The index of column `name` (matched after trimming spaces), or
    /// [`CsvIoError::MissingColumn`].
    pub fn column(&self, name: &str) -> Result<usize, CsvIoError> {
        self.headers
            .iter()
            .position(|h| h.trim() == name.trim())
            .ok_or_else(|| CsvIoError::MissingColumn {
                path: self.path.clone(),
                column: name.to_string(),
                available: self.headers.iter().map(|h| format!("`{h}`")).collect(),
            })
    }

    /// Reads the next data row into `row`; `false` at the end of the file.
    ///
    /// Errors: a blank line before this row; a row with a different number
    /// of fields than the header; invalid UTF-8; a read error.
    pub fn read_row(&mut self, row: &mut Row) -> Result<bool, CsvIoError> {
        let Some((pos, n, nend)) = self.read_raw()? else {
            return Ok(false);
        };
        self.rows += 1;
        let (number, line) = (self.rows, pos.line);
        if let Some(blank) = pos.blank {
            return Err(CsvIoError::BlankLine {
                path: self.path.clone(),
                line: blank,
                before: Some((number, line)),
            });
        }
        if nend != self.headers.len() {
            return Err(CsvIoError::Malformed {
                path: self.path.clone(),
                row: Some(number),
                line: Some(line),
                message: format!(
                    "the row has {nend} field(s), the header has {}",
                    self.headers.len()
                ),
            });
        }
        let mut bytes = std::mem::take(&mut row.text).into_bytes();
        bytes.clear();
        bytes.extend_from_slice(&self.out[..n]);
        row.text = String::from_utf8(bytes).map_err(|e| CsvIoError::Malformed {
            path: self.path.clone(),
            row: Some(number),
            line: Some(line),
            message: format!("invalid UTF-8 ({})", e.utf8_error()),
        })?;
        split_check(&row.text, &self.ends[..nend]).map_err(|message| CsvIoError::Malformed {
            path: self.path.clone(),
            row: Some(number),
            line: Some(line),
            message,
        })?;
        row.ends.clear();
        row.ends.extend_from_slice(&self.ends[..nend]);
        row.row = number;
        row.line = line;
        Ok(true)
    }

    /// Field `index` of `row` (of column `name`, for messages) parsed as a
    /// finite number, or [`CsvIoError::BadCell`] naming row, line and
    /// column.
    pub fn number(&self, row: &Row, index: usize, name: &str) -> Result<f64, CsvIoError> {
        let cell = row.field(index);
        let bad = |reason| CsvIoError::BadCell {
            path: self.path.clone(),
            row: row.row,
            line: row.line,
            column: name.to_string(),
            value: cell.to_string(),
            reason,
        };
        let v: f64 = cell.trim().parse().map_err(|_| bad("not a number"))?;
        if v.is_finite() {
            Ok(v)
        } else {
            Err(bad("not finite"))
        }
    }

    /// Parses the next record into `self.out`/`self.ends`: its position,
    /// the bytes and fields written, or `None` at the end of the file.
    fn read_raw(&mut self) -> Result<Option<(RawPos, usize, usize)>, CsvIoError> {
        use csv_core::ReadRecordResult as R;
        let (mut n, mut nend) = (0, 0);
        self.lines.next_record();
        loop {
            let input = self.input.fill_buf().map_err(|source| CsvIoError::Io {
                path: self.path.clone(),
                source,
            })?;
            let (res, nin, nout, ne) =
                self.core
                    .read_record(input, &mut self.out[n..], &mut self.ends[nend..]);
            self.lines.scan(&input[..nin]);
            self.input.consume(nin);
            n += nout;
            nend += ne;
            match res {
                R::InputEmpty => {}
                R::OutputFull => self.out.resize(2 * self.out.len(), 0),
                R::OutputEndsFull => self.ends.resize(2 * self.ends.len(), 0),
                R::Record => {
                    let pos = RawPos {
                        line: self.lines.record_line,
                        blank: self.lines.blank,
                    };
                    return Ok(Some((pos, n, nend)));
                }
                R::End => return Ok(None),
            }
        }
    }
}

/// Formats a value for CSV and messages: the shortest text that parses
/// back to the same `f64` (so files round-trip exactly). Magnitudes in
/// `[1e-4, 1e16)` and zero are written as plain decimals (`0.25`, `-3`,
/// `1234.5`, `-0`); others in scientific notation (`1e300`, `5e-324`,
/// `-1.2345e-7`), like Python's `repr` and Rust's `{:?}`, so that no value
/// takes more than 24 characters.
pub fn fmt_f64(v: f64) -> String {
    let mut s = String::new();
    push_f64(&mut s, v);
    s
}

/// Appends [`fmt_f64`]`(v)` to `buf` (no allocation once `buf` has room).
pub fn push_f64(buf: &mut String, v: f64) {
    use std::fmt::Write as _;
    let a = v.abs();
    // Writing to a String cannot fail.
    let _ = if a == 0.0 || (1e-4..1e16).contains(&a) || !a.is_finite() {
        write!(buf, "{v}")
    } else {
        write!(buf, "{v:e}")
    };
}

/// Writes named columns of equal length as CSV, atomically to `path`.
pub fn write_columns(path: &Path, columns: &[(&str, &[f64])]) -> Result<(), CsvIoError> {
    let n = columns.first().map_or(0, |c| c.1.len());
    debug_assert!(columns.iter().all(|c| c.1.len() == n));
    write_atomic(path, |w| {
        let mut out = csv::Writer::from_writer(w);
        out.write_record(columns.iter().map(|c| c.0))
            .map_err(csv_to_io)?;
        let mut row: Vec<String> = Vec::with_capacity(columns.len());
        for i in 0..n {
            row.clear();
            row.extend(columns.iter().map(|c| fmt_f64(c.1[i])));
            out.write_record(&row).map_err(csv_to_io)?;
        }
        out.flush()
    })
}

/// [`write_atomic_with`] for a CSV file: `write` writes its records to a
/// CSV writer over the temporary file, which is then flushed (a flush that
/// fails is a file system error, through `wrap`).
pub fn write_csv_atomic_with<E, W, F>(path: &Path, wrap: W, write: F) -> Result<(), E>
where
    W: Fn(CsvIoError) -> E,
    F: FnOnce(&mut csv::Writer<&mut BufWriter<&mut fs::File>>) -> Result<(), E>,
{
    write_atomic_with(path, &wrap, |w| {
        let mut out = csv::Writer::from_writer(w);
        write(&mut out)?;
        out.flush().map_err(|source| {
            wrap(CsvIoError::Io {
                path: path.to_path_buf(),
                source,
            })
        })
    })
}

/// A CSV writer's error while writing `path`, as an I/O error of that file.
pub fn csv_write_error(path: &Path, e: csv::Error) -> CsvIoError {
    CsvIoError::Io {
        path: path.to_path_buf(),
        source: csv_to_io(e),
    }
}

fn csv_to_io(e: csv::Error) -> io::Error {
    match e.into_kind() {
        csv::ErrorKind::Io(io) => io,
        other => io::Error::other(format!("{other:?}")),
    }
}

/// The directory a file at `path` would be written into, or an error if
/// it does not exist (checked before anything is written, so that a job
/// writing several files fails before the first).
pub fn target_dir(path: &Path) -> Result<PathBuf, CsvIoError> {
    let dir = match path.parent() {
        Some(d) if !d.as_os_str().is_empty() => d.to_path_buf(),
        _ => PathBuf::from("."),
    };
    if dir.is_dir() {
        Ok(dir)
    } else {
        Err(CsvIoError::Io {
            path: path.to_path_buf(),
            source: io::Error::new(
                io::ErrorKind::NotFound,
                format!("directory `{}` does not exist", dir.display()),
            ),
        })
    }
}

/// Writes a file atomically: `write` fills a temporary file in the same
/// directory as `path`, which is then flushed, synced and renamed over
/// `path`. On any error the temporary file is removed and `path` is left
/// as it was (absent or with its old contents).
pub fn write_atomic<F>(path: &Path, write: F) -> Result<(), CsvIoError>
where
    F: FnOnce(&mut BufWriter<&mut fs::File>) -> io::Result<()>,
{
    let io_err = |source| CsvIoError::Io {
        path: path.to_path_buf(),
        source,
    };
    write_atomic_with(path, |e| e, |w| write(w).map_err(io_err))
}

/// [`write_atomic`] for a `write` that fails with its own error `E` (for
/// example a job that streams its input into the file and may find a bad
/// row half-way): `write`'s error is returned as it is, the file system's
/// errors through `wrap`; either way the temporary file is removed and
/// `path` is left as it was.
pub fn write_atomic_with<E, W, F>(path: &Path, wrap: W, write: F) -> Result<(), E>
where
    W: Fn(CsvIoError) -> E,
    F: FnOnce(&mut BufWriter<&mut fs::File>) -> Result<(), E>,
{
    let io_err = |source| {
        wrap(CsvIoError::Io {
            path: path.to_path_buf(),
            source,
        })
    };
    let dir = target_dir(path).map_err(&wrap)?;
    let mut tmp = tempfile::Builder::new()
        .prefix(".hysteron-")
        .suffix(".tmp")
        .tempfile_in(&dir)
        .map_err(io_err)?;
    {
        let mut w = BufWriter::with_capacity(1 << 16, tmp.as_file_mut());
        write(&mut w)?;
        w.flush().map_err(io_err)?;
    }
    tmp.as_file().sync_all().map_err(io_err)?;
    // Temporary files are created private (0600); give the result the
    // usual permissions of a data file.
    #[cfg(unix)]
    {
        use std::os::unix::fs::PermissionsExt;
        tmp.as_file()
            .set_permissions(fs::Permissions::from_mode(0o644))
            .map_err(io_err)?;
    }
    tmp.persist(path).map_err(|e| io_err(e.error))?;
    Ok(())
}

/// Writes `contents` to `path` atomically (see [`write_atomic`]).
pub fn write_string_atomic(path: &Path, contents: &str) -> Result<(), CsvIoError> {
    write_atomic(path, |w| w.write_all(contents.as_bytes()))
}

/// The canonical form of a path that may not exist yet: the canonicalized
/// parent directory joined with the file name (or the path itself
/// canonicalized when it exists). `None` when the parent does not exist.
pub fn canonical_target(path: &Path) -> Option<PathBuf> {
    if let Ok(p) = fs::canonicalize(path) {
        return Some(p);
    }
    let name = path.file_name()?;
    let parent = match path.parent() {
        Some(d) if !d.as_os_str().is_empty() => d,
        _ => Path::new("."),
    };
    Some(fs::canonicalize(parent).ok()?.join(name))
}

/// True when `a` and `b` name the same file (after canonicalization;
/// works for files that do not exist yet).
/// `a, b, c` of the paths.
pub fn join_paths(files: &[PathBuf]) -> String {
    files
        .iter()
        .map(|p| p.display().to_string())
        .collect::<Vec<_>>()
        .join(", ")
}

/// An output path that names an input file (compared after
/// canonicalization, also when the output does not exist yet).
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
#[error("{what} `{}` is the same file as the {other_what} `{}`: refusing to overwrite it", output.display(), other.display())]
pub struct SameFile {
    /// Which output (`output`, `plot`, …).
    pub what: String,
    /// The output path.
    pub output: PathBuf,
    /// Which input it names (`input`, `model`, `output`, …).
    pub other_what: &'static str,
    /// The input path.
    pub other: PathBuf,
}

/// Refuses an output `output` (called `what`) that is one of `others`
/// (each with its name): the one check every command makes before writing.
pub fn refuse_same(
    what: &str,
    output: &Path,
    others: &[(&'static str, &Path)],
) -> Result<(), SameFile> {
    match clash(output, others) {
        Some((other_what, other)) => Err(SameFile {
            what: what.to_string(),
            output: output.to_path_buf(),
            other_what,
            other: other.to_path_buf(),
        }),
        None => Ok(()),
    }
}

/// Refuses each given output of `outputs` (each with its name) that is
/// one of `inputs` or an output before it ([`refuse_same`], against the
/// inputs first), in the order given.
pub fn refuse_overwrites(
    inputs: &[(&'static str, &Path)],
    outputs: &[(&'static str, Option<&Path>)],
) -> Result<(), SameFile> {
    let mut earlier: Vec<(&'static str, &Path)> = Vec::with_capacity(outputs.len());
    for &(what, output) in outputs {
        if let Some(output) = output {
            refuse_same(what, output, inputs)?;
            refuse_same(what, output, &earlier)?;
            earlier.push((what, output));
        }
    }
    Ok(())
}

/// The first entry of `others` that `output` names (compared with
/// [`same_file`]), for refusing to overwrite an input.
pub fn clash<'a>(
    output: &Path,
    others: &[(&'static str, &'a Path)],
) -> Option<(&'static str, &'a Path)> {
    others
        .iter()
        .find(|(_, other)| same_file(output, other))
        .copied()
}

pub fn same_file(a: &Path, b: &Path) -> bool {
    match (canonical_target(a), canonical_target(b)) {
        (Some(x), Some(y)) => x == y,
        _ => false,
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// A temporary directory holding `in.csv` with `text`, and its path.
    fn in_csv(text: &str) -> (tempfile::TempDir, PathBuf) {
        let dir = tempfile::tempdir().unwrap();
        let input = dir.path().join("in.csv");
        fs::write(&input, text).unwrap();
        (dir, input)
    }
    use rand::rngs::StdRng;
    use rand::{Rng, SeedableRng};

    /// Reads every row of `text` (written to a file) with [`CsvReader`]:
    /// the fields and lines, or the error message.
    fn rows_of(text: &str) -> Result<Vec<(Vec<String>, usize, u64)>, String> {
        let (_dir, input) = in_csv(text);
        let mut reader = CsvReader::open(&input).map_err(|e| e.to_string())?;
        let mut row = Row::default();
        let mut out = Vec::new();
        while reader.read_row(&mut row).map_err(|e| e.to_string())? {
            out.push((
                row.fields().map(String::from).collect(),
                row.row(),
                row.line(),
            ));
        }
        Ok(out)
    }

    #[test]
    fn reads_rows_verbatim_with_exact_lines() {
        let rows = rows_of("t,x\n0,0.5\n1, -1.25 \n").unwrap();
        assert_eq!(
            rows,
            vec![
                (vec!["0".into(), "0.5".into()], 1, 2),
                (vec!["1".into(), " -1.25 ".into()], 2, 3)
            ]
        );
        // \r\n, a lone \r and a quoted field spanning lines: the line where
        // each row starts (the csv crate says line 1 for the first row of a
        // \r\n file)
        let rows = rows_of("t,x\r\n0,\"a\r\nb\"\r\n1,2\r3,4\n5,6").unwrap();
        let lines: Vec<u64> = rows.iter().map(|r| r.2).collect();
        assert_eq!(lines, vec![2, 4, 5, 6]);
        assert_eq!(rows[0].0[1], "a\r\nb");
        assert_eq!(rows[3].0, vec!["5", "6"]);
    }

    #[test]
    fn blank_lines_inside_are_errors_at_the_end_accepted() {
        for (text, expected) in [
            (
                "t,x\n0,1\n\n1,2\n",
                "line 3: blank line before row 2 (line 4)",
            ),
            (
                "t,x\r\n0,1\r\n\r\n1,2\r\n",
                "line 3: blank line before row 2 (line 4)",
            ),
            ("t,x\n\n0,1\n", "line 2: blank line before row 1 (line 3)"),
            (
                "t,x\n0,1\n1,2\n\n\n3,4\n",
                "line 4: blank line before row 3 (line 6)",
            ),
            ("\nt,x\n0,1\n", "line 1: blank line before the header"),
            (
                "t,x\r0,1\r\r1,2\r",
                "line 3: blank line before row 2 (line 4)",
            ),
        ] {
            let e = rows_of(text).unwrap_err();
            assert!(e.contains(expected), "{text:?}: {e}");
            assert!(e.contains("only accepted at the end"), "{e}");
        }
        // a final line end, and blank lines after the last row, are fine
        for text in [
            "t,x\n0,1\n1,2",
            "t,x\n0,1\n1,2\n",
            "t,x\n0,1\n1,2\n\n\n",
            "t,x\r\n0,1\r\n1,2\r\n\r\n",
        ] {
            assert_eq!(rows_of(text).unwrap().len(), 2, "{text:?}");
        }
        // a line of spaces is a row, refused for its field count
        let e = rows_of("t,x\n0,1\n  \n1,2\n").unwrap_err();
        assert!(
            e.contains("row 2 (line 3)") && e.contains("1 field(s)"),
            "{e}"
        );
    }

    #[test]
    fn duplicate_column_names_are_errors() {
        for (text, expected) in [
            (
                "x,x\n1,2\n",
                "column `x` appears twice in the header (columns 1 and 2)",
            ),
            (
                "t, x ,y,x\n1,2,3,4\n",
                "column `x` appears twice in the header (columns 2 and 4)",
            ),
        ] {
            let e = rows_of(text).unwrap_err();
            assert!(e.contains(expected), "{e}");
        }
        let (_dir, input) = in_csv("x,y,x\n1,2,3\n");
        let e = read_columns(&input, &["y"]).unwrap_err().to_string();
        assert!(e.contains("column `x` appears twice"), "{e}");
    }

    #[test]
    fn numbers_are_written_shortest_and_read_back_bit_for_bit() {
        let cases = [
            (1e300, "1e300"),
            (5e-324, "5e-324"),
            (-0.0, "-0"),
            (0.0, "0"),
            (1.0 / 3.0, "0.3333333333333333"),
            (0.5, "0.5"),
            (-3.0, "-3"),
            (1234.5, "1234.5"),
            (1e-4, "0.0001"),
            (1234567890123456.0, "1234567890123456"),
            (1e16, "1e16"),
            (-1.2345e-7, "-1.2345e-7"),
            (f64::MAX, "1.7976931348623157e308"),
            (f64::MIN_POSITIVE, "2.2250738585072014e-308"),
        ];
        for (v, text) in cases {
            assert_eq!(fmt_f64(v), text);
        }
        // a few thousand values over the whole range, through a file
        let mut values: Vec<f64> = cases.iter().map(|c| c.0).collect();
        let mut rng = StdRng::seed_from_u64(0x9E37_79B9_7F4A_7C15);
        let random_bits = std::iter::repeat_with(|| f64::from_bits(rng.random()));
        let finite = random_bits.filter(|v| v.is_finite()).take(2500);
        values.extend(finite.flat_map(|v| [v, v.fract() * 1e3]));
        for v in &values {
            let text = fmt_f64(*v);
            assert!(text.len() <= 24, "{text}");
            assert_eq!(
                text.parse::<f64>().unwrap().to_bits(),
                v.to_bits(),
                "{text}"
            );
        }
        let dir = tempfile::tempdir().unwrap();
        let path = dir.path().join("v.csv");
        write_columns(&path, &[("v", &values)]).unwrap();
        let back = read_columns(&path, &["v"]).unwrap();
        assert_eq!(back.values[0].len(), values.len());
        for (a, b) in values.iter().zip(&back.values[0]) {
            assert_eq!(a.to_bits(), b.to_bits());
        }
    }

    #[test]
    fn time_steps_are_checked_while_streaming() {
        let (_dir, input) = in_csv("t,x\n0,1\n0.5,1\n1,1\n1.5,1\n");
        assert_eq!(read_time_step(&input, "t").unwrap(), 0.5);
        fs::write(&input, "t,x\n0,1\n0.5,1\n1.2,1\n").unwrap();
        let e = read_time_step(&input, "t").unwrap_err().to_string();
        assert!(e.contains("row 3 (line 4), column `t`: time step"), "{e}");
        fs::write(&input, "t,x\n0,1\n0,1\n").unwrap();
        let e = read_time_step(&input, "t").unwrap_err().to_string();
        assert!(
            e.contains("row 2 (line 3)") && e.contains("does not increase"),
            "{e}"
        );
        fs::write(&input, "t,x\n0,1\n").unwrap();
        let e = read_time_step(&input, "t").unwrap_err().to_string();
        assert!(
            e.contains("row 1 (line 2)") && e.contains("at least 2 rows"),
            "{e}"
        );
    }

    #[test]
    fn bad_cells_name_row_line_and_column() {
        let (_dir, input) = in_csv("t,x\n0,1\n1,abc\n");
        let e = read_columns(&input, &["x"]).unwrap_err().to_string();
        assert!(e.contains("row 2 (line 3), column `x`"), "{e}");
        fs::write(&input, "t,x\n0,1\n1,NaN\n").unwrap();
        let e = read_columns(&input, &["x"]).unwrap_err().to_string();
        assert!(e.contains("not finite"), "{e}");
    }

    #[test]
    fn reads_two_columns_checking_cells_in_order() {
        let (_dir, input) = in_csv("t, x ,F\n0,0.5,1\n1,-1.25,2\n");
        let c = read_columns(&input, &["x", "F"]).unwrap();
        assert_eq!(c.indices, vec![1, 2]);
        assert_eq!(c.values, vec![vec![0.5, -1.25], vec![1.0, 2.0]]);
        assert_eq!(c.lines, vec![2, 3]);
        fs::write(&input, "t,x,F\n0,0.5,1\n1,abc,NaN\n").unwrap();
        let e = read_columns(&input, &["F", "x"]).unwrap_err().to_string();
        assert!(
            e.contains("row 2 (line 3), column `F`: `NaN` is not finite"),
            "{e}"
        );
        let e = read_columns(&input, &["x", "G"]).unwrap_err().to_string();
        assert!(e.contains("no column `G`"), "{e}");
    }

    #[test]
    fn same_file_sees_through_relative_paths() {
        let dir = tempfile::tempdir().unwrap();
        let a = dir.path().join("a.csv");
        fs::write(&a, "x\n1\n").unwrap();
        let sub = dir.path().join("sub");
        fs::create_dir(&sub).unwrap();
        assert!(same_file(&a, &sub.join("..").join("a.csv")));
        assert!(!same_file(&a, &dir.path().join("b.csv")));
        assert!(same_file(
            &dir.path().join("new.csv"),
            &sub.join("../new.csv")
        ));
    }
}

/// Where a model failed while running over a column of a data file: the
/// sample, its row and line in the file, the column and value, and the
/// operator's error (without the sample wrapper).
#[derive(Debug)]
pub struct SampleFailure {
    /// The model spec.
    pub model: PathBuf,
    /// The data file.
    pub file: PathBuf,
    /// What the file is called in messages (`input`, `data`).
    pub role: &'static str,
    /// 0-based sample index, 1-based data row and file line, if known.
    pub at: Option<(usize, usize, u64)>,
    /// The column the model ran over.
    pub column: String,
    /// The input value at that sample, if known.
    pub value: Option<f64>,
    /// The operator's error.
    pub error: crate::operators::Error,
}

impl SampleFailure {
    /// Locates `error` (an [`Error::AtSample`](crate::operators::Error::AtSample)
    /// or any other) in a run over `values`, whose records sit at `lines`.
    pub fn locate(
        model: &Path,
        file: &Path,
        role: &'static str,
        column: &str,
        values: &[f64],
        lines: &[u64],
        error: crate::operators::Error,
    ) -> Self {
        Self::locate_in(model, file, role, column, error, |i| {
            (
                i,
                i + 1,
                lines.get(i).copied().unwrap_or(i as u64 + 2),
                values.get(i).copied(),
            )
        })
    }

    /// Like [`locate`](Self::locate) for a run over part of a file (a
    /// chunk of a streamed record): `at(i)` gives, for the index `i` within
    /// the run, the sample index in the whole record, its data row, its
    /// line in the file and the input value.
    pub fn locate_in(
        model: &Path,
        file: &Path,
        role: &'static str,
        column: &str,
        error: crate::operators::Error,
        at: impl Fn(usize) -> (usize, usize, u64, Option<f64>),
    ) -> Self {
        let (index, error) = match error {
            crate::operators::Error::AtSample { index, source } => (Some(index), *source),
            other => (None, other),
        };
        let at = index.map(&at);
        SampleFailure {
            model: model.to_path_buf(),
            file: file.to_path_buf(),
            role,
            at: at.map(|(i, row, line, _)| (i, row, line)),
            column: column.to_string(),
            value: at.and_then(|a| a.3),
            error,
        }
    }

    /// ` at sample i: input `f`, row r (line l), column `c` = v: error`.
    pub fn location(&self) -> String {
        let (role, file, column) = (self.role, self.file.display(), &self.column);
        let place = match self.at {
            Some((i, row, line)) => {
                format!(
                    " at sample {i}: {role} `{file}`, row {row} (line {line}), column `{column}`"
                )
            }
            None => format!(" on {role} `{file}`, column `{column}`"),
        };
        let value = self
            .value
            .map_or_else(String::new, |v| format!(" = {}", fmt_f64(v)));
        format!("{place}{value}: {}", self.error)
    }
}

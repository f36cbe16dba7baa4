//! CSV input and output for the command-line program, and atomic file
//! writing.
//!
//! * [`read_column`] reads a CSV file with a header row and parses one
//!   column as finite `f64` values, keeping every record verbatim so they
//!   can be written back with an extra column; [`read_columns`] parses
//!   several;
//! * [`write_columns`] writes named `f64` columns;
//! * [`write_atomic`] writes any file through a temporary file in the
//!   destination's directory, renamed over the destination only when
//!   complete, so a reader never sees a half-written file and a failed
//!   write leaves no file behind.
//!
//! Every error is a [`CsvIoError`] whose message is one line naming the
//! file and, where relevant, the row (1-based data row, and the line in the
//! file) and the column.

use std::fs;
use std::io::{self, BufWriter, Write};
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

/// A CSV table read by [`read_column`]: the header, the records verbatim
/// and the selected column parsed.
#[derive(Debug, Clone, PartialEq)]
pub struct Table {
    /// Column names, as in the header.
    pub headers: csv::StringRecord,
    /// Data records, verbatim.
    pub records: Vec<csv::StringRecord>,
    /// Index of the selected column.
    pub column: usize,
    /// The selected column's values, one per record (all finite).
    pub values: Vec<f64>,
    /// 1-based line in the file of each record (for messages).
    pub lines: Vec<u64>,
}

/// Reads `path` (a CSV file with a header row) and parses column `column`
/// (matched after trimming spaces) as finite numbers.
///
/// Errors: the file cannot be read; no header; no such column; no data
/// rows; a row with a different number of fields; a cell that is not a
/// number or not finite (`NaN`, `inf`), naming row, line and column.
pub fn read_column(path: &Path, column: &str) -> Result<Table, CsvIoError> {
    let mut read = read_parsed(path, &[column])?;
    Ok(Table {
        headers: read.headers,
        records: read.records,
        column: read.indices[0],
        values: read.values.swap_remove(0),
        lines: read.lines,
    })
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

/// Reads `path` like [`read_column`], parsing each of `columns` (in that
/// order; a column may be named twice) as finite numbers. A row's cells
/// are checked in the order of `columns`, so the first bad cell of the
/// first bad row is the one reported.
pub fn read_columns(path: &Path, columns: &[&str]) -> Result<Columns, CsvIoError> {
    let read = read_parsed(path, columns)?;
    Ok(Columns {
        headers: read.headers,
        indices: read.indices,
        values: read.values,
        lines: read.lines,
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

/// Reads the time column `column` of `path` (like [`read_columns`]) and
/// returns its sample period: the mean step `(t_last − t_first)/(n − 1)`.
///
/// The column must have at least two rows, increase, and be uniformly
/// spaced: every step within [`TIME_STEP_REL_TOL`] (relative) of the first
/// one. Otherwise [`CsvIoError::NotUniform`] names the row where it breaks.
pub fn read_time_step(path: &Path, column: &str) -> Result<f64, CsvIoError> {
    let read = read_columns(path, &[column])?;
    let name = read.headers[read.indices[0]].trim().to_string();
    uniform_step(path, &name, &read.values[0], &read.lines)
}

/// The sample period of a time column (see [`read_time_step`]); `lines`
/// are the file lines of its rows.
pub fn uniform_step(
    path: &Path,
    column: &str,
    t: &[f64],
    lines: &[u64],
) -> Result<f64, CsvIoError> {
    let err = |i: usize, message: String| CsvIoError::NotUniform {
        path: path.to_path_buf(),
        row: i + 1,
        line: lines.get(i).copied().unwrap_or(i as u64 + 2),
        column: column.to_string(),
        message,
    };
    let n = t.len();
    if n < 2 {
        return Err(err(
            0,
            format!("a time column needs at least 2 rows to give a sample period (got {n})"),
        ));
    }
    let first = t[1] - t[0];
    if !(first > 0.0 && first.is_finite()) {
        return Err(err(
            1,
            format!("time does not increase ({} after {})", t[1], t[0]),
        ));
    }
    for i in 2..n {
        let step = t[i] - t[i - 1];
        if (step - first).abs() > TIME_STEP_REL_TOL * first {
            return Err(err(
                i,
                format!(
                    "time step {step} (from {} to {}) differs from the first step {first} \
                     by more than {TIME_STEP_REL_TOL:e} relative (more than the rounding of \
                     written time stamps): the time column must be uniformly spaced",
                    t[i - 1],
                    t[i]
                ),
            ));
        }
    }
    Ok((t[n - 1] - t[0]) / (n - 1) as f64)
}

struct Parsed {
    headers: csv::StringRecord,
    records: Vec<csv::StringRecord>,
    indices: Vec<usize>,
    values: Vec<Vec<f64>>,
    lines: Vec<u64>,
}

fn read_parsed(path: &Path, columns: &[&str]) -> Result<Parsed, CsvIoError> {
    let file = fs::File::open(path).map_err(|source| CsvIoError::Io {
        path: path.to_path_buf(),
        source,
    })?;
    let mut reader = csv::ReaderBuilder::new()
        .has_headers(true)
        .flexible(false)
        .from_reader(io::BufReader::new(file));
    let malformed = |e: csv::Error, row: Option<usize>| {
        let line = e.position().map(|p| p.line());
        let message = match e.kind() {
            csv::ErrorKind::UnequalLengths {
                expected_len, len, ..
            } => format!("the row has {len} field(s), the header has {expected_len}"),
            csv::ErrorKind::Io(io) => io.to_string(),
            csv::ErrorKind::Utf8 { err, .. } => format!("invalid UTF-8 ({err})"),
            _ => e.to_string(),
        };
        CsvIoError::Malformed {
            path: path.to_path_buf(),
            row,
            line,
            message,
        }
    };
    let headers = reader.headers().map_err(|e| malformed(e, None))?.clone();
    if headers.is_empty() || (headers.len() == 1 && headers[0].trim().is_empty()) {
        return Err(CsvIoError::NoHeader {
            path: path.to_path_buf(),
        });
    }
    let indices = columns
        .iter()
        .map(|column| {
            headers
                .iter()
                .position(|h| h.trim() == column.trim())
                .ok_or_else(|| CsvIoError::MissingColumn {
                    path: path.to_path_buf(),
                    column: column.to_string(),
                    available: headers.iter().map(|h| format!("`{h}`")).collect(),
                })
        })
        .collect::<Result<Vec<usize>, _>>()?;
    let names: Vec<String> = indices
        .iter()
        .map(|&i| headers[i].trim().to_string())
        .collect();
    let mut records = Vec::new();
    let mut values = vec![Vec::new(); columns.len()];
    let mut lines = Vec::new();
    for (i, rec) in reader.records().enumerate() {
        let row = i + 1;
        let rec = rec.map_err(|e| malformed(e, Some(row)))?;
        let line = rec.position().map_or(row as u64 + 1, |p| p.line());
        for ((&index, name), column) in indices.iter().zip(&names).zip(&mut values) {
            let cell = &rec[index];
            let bad = |reason| CsvIoError::BadCell {
                path: path.to_path_buf(),
                row,
                line,
                column: name.clone(),
                value: cell.to_string(),
                reason,
            };
            let v: f64 = cell.trim().parse().map_err(|_| bad("not a number"))?;
            if !v.is_finite() {
                return Err(bad("not finite"));
            }
            column.push(v);
        }
        lines.push(line);
        records.push(rec);
    }
    if records.is_empty() {
        return Err(CsvIoError::NoRows {
            path: path.to_path_buf(),
        });
    }
    Ok(Parsed {
        headers,
        records,
        indices,
        values,
        lines,
    })
}

/// Formats a value for CSV: the shortest text that parses back to the same
/// `f64` (so files round-trip exactly).
pub fn fmt_f64(v: f64) -> String {
    format!("{v}")
}

/// Writes `table`'s header and records with one more column, `name`,
/// holding `extra` (one value per record), atomically to `path`.
pub fn write_with_column(
    path: &Path,
    table: &Table,
    name: &str,
    extra: &[f64],
) -> Result<(), CsvIoError> {
    debug_assert_eq!(table.records.len(), extra.len());
    write_atomic(path, |w| {
        let mut out = csv::Writer::from_writer(w);
        let mut header = table.headers.clone();
        header.push_field(name);
        out.write_record(&header).map_err(csv_to_io)?;
        let mut row = csv::StringRecord::new();
        for (rec, v) in table.records.iter().zip(extra) {
            row.clone_from(rec);
            row.push_field(&fmt_f64(*v));
            out.write_record(&row).map_err(csv_to_io)?;
        }
        out.flush()
    })
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
    let dir = target_dir(path)?;
    let mut tmp = tempfile::Builder::new()
        .prefix(".hysteron-")
        .suffix(".tmp")
        .tempfile_in(&dir)
        .map_err(io_err)?;
    {
        let mut w = BufWriter::new(tmp.as_file_mut());
        write(&mut w).map_err(io_err)?;
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

/// The first entry of `others` that `output` names (compared with
/// [`same_file`]), for refusing to overwrite an input.
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

    #[test]
    fn reads_a_column_and_writes_it_back_with_y() {
        let dir = tempfile::tempdir().unwrap();
        let input = dir.path().join("in.csv");
        fs::write(&input, "t,x\n0,0.5\n1, -1.25 \n").unwrap();
        let table = read_column(&input, "x").unwrap();
        assert_eq!(table.values, vec![0.5, -1.25]);
        assert_eq!(table.lines, vec![2, 3]);
        let out = dir.path().join("out.csv");
        write_with_column(&out, &table, "y", &[1.0, 0.1]).unwrap();
        assert_eq!(
            fs::read_to_string(&out).unwrap(),
            "t,x,y\n0,0.5,1\n1, -1.25 ,0.1\n"
        );
    }

    #[test]
    fn bad_cells_name_row_line_and_column() {
        let dir = tempfile::tempdir().unwrap();
        let input = dir.path().join("in.csv");
        fs::write(&input, "t,x\n0,1\n1,abc\n").unwrap();
        let e = read_column(&input, "x").unwrap_err().to_string();
        assert!(e.contains("row 2 (line 3), column `x`"), "{e}");
        fs::write(&input, "t,x\n0,1\n1,NaN\n").unwrap();
        let e = read_column(&input, "x").unwrap_err().to_string();
        assert!(e.contains("not finite"), "{e}");
    }

    #[test]
    fn reads_two_columns_checking_cells_in_order() {
        let dir = tempfile::tempdir().unwrap();
        let input = dir.path().join("in.csv");
        fs::write(&input, "t, x ,F\n0,0.5,1\n1,-1.25,2\n").unwrap();
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
        let (index, error) = match error {
            crate::operators::Error::AtSample { index, source } => (Some(index), *source),
            other => (None, other),
        };
        SampleFailure {
            model: model.to_path_buf(),
            file: file.to_path_buf(),
            role,
            at: index.map(|i| (i, i + 1, lines.get(i).copied().unwrap_or(i as u64 + 2))),
            column: column.to_string(),
            value: index.and_then(|i| values.get(i).copied()),
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
        let value = self.value.map_or_else(String::new, |v| format!(" = {v}"));
        format!("{place}{value}: {}", self.error)
    }
}

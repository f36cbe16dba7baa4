//! `csv_read`: the CLI's CSV readers (`read_columns`, `read_time_step`
//! and the row reader `CsvReader` under them) on arbitrary file contents
//! and column names (the bytes before the first NUL are up to four names
//! separated by `\x01`, the rest is the file). Checks: no panic; every
//! value read is finite; one value per data row in every column; the
//! indices name the requested columns; line numbers increase; reading the
//! first column row by row agrees with `read_columns`; a time step is
//! finite and positive.
#![no_main]

use hysteron_cli::csvio::{read_columns, read_time_step, CsvReader, Row};
use libfuzzer_sys::fuzz_target;
use std::path::PathBuf;
use std::sync::OnceLock;

/// One file in a temporary directory that lives as long as the process.
fn path() -> &'static PathBuf {
    static PATH: OnceLock<(tempfile::TempDir, PathBuf)> = OnceLock::new();
    &PATH
        .get_or_init(|| {
            let dir = tempfile::tempdir().expect("a temporary directory");
            let path = dir.path().join("record.csv");
            (dir, path)
        })
        .1
}

fuzz_target!(|data: &[u8]| {
    let split = data.iter().position(|&b| b == 0).unwrap_or(data.len());
    let names = String::from_utf8_lossy(&data[..split]);
    let columns: Vec<&str> = names.split('\x01').take(4).collect();
    let path = path();
    std::fs::write(path, data.get(split + 1..).unwrap_or(&[])).expect("write the record");
    let first = columns[0];
    // the first column row by row
    let one: Option<Vec<f64>> = (|| {
        let mut reader = CsvReader::open(path).ok()?;
        let index = reader.column(first).ok()?;
        assert_eq!(reader.headers()[index].trim(), first.trim());
        let mut row = Row::default();
        let mut values = Vec::new();
        let mut line = 0;
        while reader.read_row(&mut row).ok()? {
            assert_eq!(row.len(), reader.headers().len());
            assert!(row.line() > line, "line {} after {line}", row.line());
            line = row.line();
            let v = reader.number(&row, index, first).ok()?;
            assert!(v.is_finite());
            values.push(v);
        }
        Some(values)
    })();
    let many = read_columns(path, &columns);
    if let Ok(c) = &many {
        assert_eq!(c.indices.len(), columns.len());
        assert_eq!(c.values.len(), columns.len());
        for ((&i, v), name) in c.indices.iter().zip(&c.values).zip(&columns) {
            assert_eq!(c.headers[i].trim(), name.trim());
            assert_eq!(v.len(), c.lines.len());
            assert!(v.iter().all(|v| v.is_finite()));
        }
        assert!(c.lines.windows(2).all(|w| w[0] < w[1]), "lines increase");
    }
    if let Ok(c) = &many {
        let one = one.expect("the row reader fails where read_columns reads");
        assert_eq!(
            one.iter().map(|v| v.to_bits()).collect::<Vec<_>>(),
            c.values[0].iter().map(|v| v.to_bits()).collect::<Vec<_>>()
        );
    }
    if let Ok(dt) = read_time_step(path, first) {
        assert!(dt.is_finite() && dt > 0.0, "time step {dt}");
    }
});

//! Named columns of `f64` as an Apache Parquet file: one `REQUIRED DOUBLE`
//! column per name, in one row group, uncompressed (PLAIN/dictionary
//! encodings as the writer chooses), written atomically
//! ([`csvio::write_atomic_with`]). Readers such as pandas, polars, Arrow
//! and DuckDB read it as a table with the same column names as the CSV
//! form.

use crate::csvio::{self, CsvIoError};
use parquet::basic::{Repetition, Type as PhysicalType};
use parquet::data_type::DoubleType;
use parquet::errors::ParquetError;
use parquet::file::properties::WriterProperties;
use parquet::file::writer::SerializedFileWriter;
use parquet::schema::types::Type;
use std::io;
use std::path::Path;
use std::sync::Arc;

/// Whether `path` names a Parquet file (its extension is `parquet`, in
/// any case).
pub fn is_parquet(path: &Path) -> bool {
    path.extension()
        .and_then(|e| e.to_str())
        .is_some_and(|e| e.eq_ignore_ascii_case("parquet"))
}

/// Writes named columns of equal length as a Parquet file, atomically to
/// `path` (on an error no file is left behind, and a file that was there
/// is unchanged).
///
/// # Errors
/// [`CsvIoError::Io`] naming `path` if the file system or the Parquet
/// writer fails (such as two columns with one name).
pub fn write_columns(path: &Path, columns: &[(&str, &[f64])]) -> Result<(), CsvIoError> {
    let io_err = |e: ParquetError| CsvIoError::Io {
        path: path.to_path_buf(),
        source: io::Error::other(e.to_string()),
    };
    let fields = columns
        .iter()
        .map(|(name, _)| {
            Type::primitive_type_builder(name, PhysicalType::DOUBLE)
                .with_repetition(Repetition::REQUIRED)
                .build()
                .map(Arc::new)
        })
        .collect::<Result<Vec<_>, _>>()
        .map_err(io_err)?;
    let schema = Type::group_type_builder("schema")
        .with_fields(fields)
        .build()
        .map_err(io_err)?;
    let properties = WriterProperties::builder().build();
    csvio::write_atomic_with(
        path,
        |e| e,
        |w| {
            let mut writer = SerializedFileWriter::new(w, Arc::new(schema), Arc::new(properties))
                .map_err(io_err)?;
            let mut group = writer.next_row_group().map_err(io_err)?;
            let mut values = columns.iter().map(|c| c.1);
            while let Some(mut column) = group.next_column().map_err(io_err)? {
                let data = values.next().unwrap_or(&[]);
                column
                    .typed::<DoubleType>()
                    .write_batch(data, None, None)
                    .map_err(io_err)?;
                column.close().map_err(io_err)?;
            }
            group.close().map_err(io_err)?;
            writer.close().map_err(io_err)?;
            Ok(())
        },
    )
}

//! A small column table (one row per sweep run) and its files: Apache
//! Parquet (the `parquet` crate's column writer, uncompressed, one row
//! group), CSV (RFC 4180, numbers in shortest round-trip form) or JSON (a
//! list of row objects). Floats keep every bit in all three.

use std::path::Path;
use std::sync::Arc;

use parquet::basic::{ConvertedType, Repetition, Type as PhysicalType};
use parquet::data_type::{ByteArray, ByteArrayType, DoubleType, Int64Type};
use parquet::file::properties::WriterProperties;
use parquet::file::writer::SerializedFileWriter;
use parquet::schema::types::Type as ParquetType;

use super::atomic::write_atomic;
use super::recording::ExportError;

/// One column's values.
#[derive(Debug, Clone, PartialEq)]
pub enum Column {
    /// 64-bit integers.
    Int(Vec<i64>),
    /// 64-bit floats (NaN where there is no value).
    Float(Vec<f64>),
    /// Text, `None` where there is no value.
    Text(Vec<Option<String>>),
}

impl Column {
    fn len(&self) -> usize {
        match self {
            Column::Int(v) => v.len(),
            Column::Float(v) => v.len(),
            Column::Text(v) => v.len(),
        }
    }

    fn json(&self, row: usize) -> serde_json::Value {
        match self {
            Column::Int(v) => v[row].into(),
            // JSON has no NaN: a missing number is null.
            Column::Float(v) => {
                serde_json::Number::from_f64(v[row]).map_or(serde_json::Value::Null, Into::into)
            }
            Column::Text(v) => v[row].clone().map_or(serde_json::Value::Null, Into::into),
        }
    }
}

/// Named columns of equal length.
#[derive(Debug, Clone, PartialEq, Default)]
pub struct Table {
    /// (name, values) in column order.
    pub columns: Vec<(String, Column)>,
}

impl Table {
    /// Rows in the table.
    pub fn rows(&self) -> usize {
        self.columns.first().map_or(0, |(_, c)| c.len())
    }

    fn check(&self) -> Result<(), ExportError> {
        let n = self.rows();
        match self.columns.iter().find(|(_, c)| c.len() != n) {
            Some((name, c)) => Err(ExportError::BadTable(format!(
                "column {name} has {} rows, the first column {n}",
                c.len()
            ))),
            None => Ok(()),
        }
    }

    /// The table as CSV text: a header of names, then one line per row.
    pub fn to_csv(&self) -> Result<String, ExportError> {
        self.check()?;
        let mut out = String::new();
        let names: Vec<String> = self.columns.iter().map(|(n, _)| quote(n)).collect();
        out.push_str(&names.join(","));
        out.push('\n');
        for r in 0..self.rows() {
            let cells: Vec<String> = self
                .columns
                .iter()
                .map(|(_, c)| match c {
                    Column::Int(v) => v[r].to_string(),
                    Column::Float(v) if v[r].is_nan() => String::new(),
                    Column::Float(v) => v[r].to_string(),
                    Column::Text(v) => v[r].as_deref().map_or(String::new(), quote),
                })
                .collect();
            out.push_str(&cells.join(","));
            out.push('\n');
        }
        Ok(out)
    }

    /// The table as a JSON list of row objects (missing values null).
    pub fn to_json(&self) -> Result<String, ExportError> {
        self.check()?;
        let rows: Vec<serde_json::Value> = (0..self.rows())
            .map(|r| {
                serde_json::Value::Object(self.columns.iter().map(|(n, c)| (n.clone(), c.json(r))).collect())
            })
            .collect();
        serde_json::to_string_pretty(&rows).map_err(|e| ExportError::BadTable(e.to_string()))
    }

    /// The table as an Apache Parquet file's bytes.
    pub fn to_parquet(&self) -> Result<Vec<u8>, ExportError> {
        self.check()?;
        let bad = |e: parquet::errors::ParquetError| ExportError::BadTable(format!("parquet: {e}"));
        let fields: Vec<_> = self
            .columns
            .iter()
            .map(|(name, c)| {
                let (physical, repetition, text) = match c {
                    Column::Int(_) => (PhysicalType::INT64, Repetition::OPTIONAL, false),
                    Column::Float(_) => (PhysicalType::DOUBLE, Repetition::OPTIONAL, false),
                    Column::Text(_) => (PhysicalType::BYTE_ARRAY, Repetition::OPTIONAL, true),
                };
                let mut b = ParquetType::primitive_type_builder(name, physical).with_repetition(repetition);
                if text {
                    b = b.with_converted_type(ConvertedType::UTF8);
                }
                b.build().map(Arc::new)
            })
            .collect::<Result<_, _>>()
            .map_err(bad)?;
        let schema = ParquetType::group_type_builder("table")
            .with_fields(fields)
            .build()
            .map_err(bad)?;
        let mut bytes = Vec::new();
        {
            let props = Arc::new(WriterProperties::builder().build());
            let mut writer = SerializedFileWriter::new(&mut bytes, Arc::new(schema), props).map_err(bad)?;
            let mut group = writer.next_row_group().map_err(bad)?;
            let mut k = 0;
            while let Some(mut col) = group.next_column().map_err(bad)? {
                match &self.columns[k].1 {
                    Column::Int(v) => {
                        // Optional (all present), as readers build the same
                        // table in memory: nullable columns throughout.
                        let levels = vec![1i16; v.len()];
                        col.typed::<Int64Type>()
                            .write_batch(v, Some(&levels), None)
                            .map_err(bad)?;
                    }
                    Column::Float(v) => {
                        let levels: Vec<i16> = v.iter().map(|x| i16::from(!x.is_nan())).collect();
                        let present: Vec<f64> = v.iter().copied().filter(|x| !x.is_nan()).collect();
                        col.typed::<DoubleType>()
                            .write_batch(&present, Some(&levels), None)
                            .map_err(bad)?;
                    }
                    Column::Text(v) => {
                        let levels: Vec<i16> = v.iter().map(|x| i16::from(x.is_some())).collect();
                        let present: Vec<ByteArray> =
                            v.iter().flatten().map(|s| ByteArray::from(s.as_str())).collect();
                        col.typed::<ByteArrayType>()
                            .write_batch(&present, Some(&levels), None)
                            .map_err(bad)?;
                    }
                }
                col.close().map_err(bad)?;
                k += 1;
            }
            group.close().map_err(bad)?;
            writer.close().map_err(bad)?;
        }
        Ok(bytes)
    }

    /// Writes the table atomically, by extension: `.parquet`, `.csv` or `.json`.
    pub fn write(&self, path: impl AsRef<Path>) -> Result<(), ExportError> {
        let path = path.as_ref();
        let ext = path
            .extension()
            .and_then(|e| e.to_str())
            .unwrap_or("")
            .to_ascii_lowercase();
        let bytes = match ext.as_str() {
            "parquet" => self.to_parquet()?,
            "csv" => self.to_csv()?.into_bytes(),
            "json" => self.to_json()?.into_bytes(),
            _ => {
                return Err(ExportError::BadTable(format!(
                    "{}: give a .parquet, .csv or .json file",
                    path.display()
                )))
            }
        };
        write_atomic(path, &bytes)
    }
}

fn quote(text: &str) -> String {
    if text.contains([',', '"', '\n', '\r']) {
        format!("\"{}\"", text.replace('"', "\"\""))
    } else {
        text.to_string()
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn table() -> Table {
        Table {
            columns: vec![
                ("run".into(), Column::Int(vec![0, 1])),
                (
                    "bodies[ball].restitution".into(),
                    Column::Float(vec![0.1, f64::NAN]),
                ),
                (
                    "error".into(),
                    Column::Text(vec![None, Some("bad, \"value\"".into())]),
                ),
            ],
        }
    }

    #[test]
    fn csv_and_json_keep_values_and_mark_missing_ones() {
        let csv = table().to_csv().unwrap();
        assert_eq!(
            csv,
            "run,bodies[ball].restitution,error\n0,0.1,\n1,,\"bad, \"\"value\"\"\"\n"
        );
        let json: serde_json::Value = serde_json::from_str(&table().to_json().unwrap()).unwrap();
        assert_eq!(json[0]["bodies[ball].restitution"], 0.1);
        assert!(json[1]["bodies[ball].restitution"].is_null());
        assert_eq!(json[1]["error"], "bad, \"value\"");
    }

    #[test]
    fn parquet_has_the_magic_and_every_column_name() {
        let bytes = table().to_parquet().unwrap();
        assert_eq!(&bytes[..4], b"PAR1");
        assert_eq!(&bytes[bytes.len() - 4..], b"PAR1");
        let path = std::env::temp_dir().join(format!("tumble-table-{}.parquet", std::process::id()));
        std::fs::write(&path, &bytes).unwrap();
        let file = std::fs::File::open(&path).unwrap();
        let reader = parquet::file::serialized_reader::SerializedFileReader::new(file).unwrap();
        let _ = std::fs::remove_file(&path);
        use parquet::file::reader::FileReader;
        let meta = reader.metadata().file_metadata();
        assert_eq!(meta.num_rows(), 2);
        let names: Vec<&str> = meta.schema_descr().columns().iter().map(|c| c.name()).collect();
        assert_eq!(names, ["run", "bodies[ball].restitution", "error"]);
    }

    #[test]
    fn ragged_tables_are_refused() {
        let mut t = table();
        t.columns.push(("x".into(), Column::Int(vec![1])));
        assert!(t.to_csv().is_err() && t.to_parquet().is_err());
    }
}

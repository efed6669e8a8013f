//! Tables stored as one compound dataset (one named field per column): a single HDF5 object per
//! table keeps the object count per run small, and h5py reads a column as `dataset["name"]`.

use hdf5_pure::{CharacterSet, CompoundTypeBuilder, Dataset, Datatype, StringPadding};

use super::layout_error::LayoutError;
use super::table::ColumnData;

/// One column of a table to write.
#[derive(Clone, Copy, Debug)]
pub enum Field<'a> {
    /// 64-bit floats.
    F64(&'a [f64]),
    /// 32-bit unsigned integers.
    U32(&'a [u32]),
    /// 64-bit signed integers.
    I64(&'a [i64]),
    /// Booleans as 8-bit unsigned integers (0 or 1).
    Bool(&'a [bool]),
    /// Text as fixed-length UTF-8, as wide as the longest value (at least 1 byte), null-padded.
    Text(&'a [String]),
}

impl Field<'_> {
    fn len(&self) -> usize {
        match self {
            Field::F64(v) => v.len(),
            Field::U32(v) => v.len(),
            Field::I64(v) => v.len(),
            Field::Bool(v) => v.len(),
            Field::Text(v) => v.len(),
        }
    }
}

/// The width of a text field: its longest value, at least 1 byte.
fn text_width(values: &[String]) -> usize {
    values.iter().map(String::len).max().unwrap_or(0).max(1)
}

/// The compound datatype, little-endian packed element bytes and row count of a table
/// (columns must have equal lengths).
pub fn encode(fields: &[(&str, Field<'_>)]) -> (Datatype, Vec<u8>, u64) {
    let rows = fields.first().map_or(0, |(_, f)| f.len());
    let mut builder = CompoundTypeBuilder::new();
    for (name, field) in fields {
        debug_assert_eq!(field.len(), rows, "column {name} has a different length");
        builder = match field {
            Field::F64(_) => builder.f64_field(name),
            Field::U32(_) => builder.u32_field(name),
            Field::I64(_) => builder.i64_field(name),
            Field::Bool(_) => builder.u8_field(name),
            Field::Text(v) => builder.field(
                name,
                Datatype::String {
                    size: text_width(v) as u32,
                    padding: StringPadding::NullPad,
                    charset: CharacterSet::Utf8,
                },
            ),
        };
    }
    let datatype = builder.build().expect("a table has at least one column");
    let mut bytes = Vec::with_capacity(rows * datatype.type_size() as usize);
    for row in 0..rows {
        for (_, field) in fields {
            match field {
                Field::F64(v) => bytes.extend_from_slice(&v[row].to_le_bytes()),
                Field::U32(v) => bytes.extend_from_slice(&v[row].to_le_bytes()),
                Field::I64(v) => bytes.extend_from_slice(&v[row].to_le_bytes()),
                Field::Bool(v) => bytes.push(u8::from(v[row])),
                Field::Text(v) => {
                    let start = bytes.len();
                    bytes.extend_from_slice(v[row].as_bytes());
                    bytes.resize(start + text_width(v), 0);
                }
            }
        }
    }
    (datatype, bytes, rows as u64)
}

/// Tables with at least this many rows are compressed (shuffle + deflate).
const COMPRESS_MIN_ROWS: u64 = 64;
/// Largest chunk (rows) of a table.
const MAX_CHUNK_ROWS: u64 = 1 << 14;
/// Deflate level: fast, and most of the gain for smooth float series comes from the shuffle.
pub const DEFLATE_LEVEL: u32 = 1;

/// Stages a compound table in `b`: chunked with a Fletcher-32 checksum of each chunk, so that a
/// damaged byte is an error when read (by demsweep, h5py or any libhdf5 reader), not a value; long
/// tables also compressed (shuffle + deflate). An empty table is a plain empty dataset.
pub fn stage(b: &mut hdf5_pure::DatasetBuilder, fields: &[(&str, Field<'_>)]) {
    let (datatype, bytes, rows) = encode(fields);
    b.with_compound_data(datatype, bytes, rows);
    checksummed(b, &[rows]);
}

/// Chunks a dataset of `shape` along its first axis with a Fletcher-32 checksum of each chunk, and
/// compresses it when it has [`COMPRESS_MIN_ROWS`] rows or more (an empty one is left plain).
pub fn checksummed(b: &mut hdf5_pure::DatasetBuilder, shape: &[u64]) {
    if shape.contains(&0) {
        b.with_shape(shape);
        return;
    }
    let mut chunks = shape.to_vec();
    chunks[0] = shape[0].min(MAX_CHUNK_ROWS);
    b.with_chunks(&chunks);
    if shape[0] >= COMPRESS_MIN_ROWS {
        b.with_shuffle().with_deflate(DEFLATE_LEVEL);
    }
    b.with_fletcher32();
}

/// Deflate's largest compression ratio (1032:1): no dataset of a file decodes to more than this
/// many times the file's size.
const MAX_EXPANSION: u64 = 1032;

/// The most bytes a dataset of the file at `path` can hold: [`MAX_EXPANSION`] times its size.
pub fn read_limit(path: &std::path::Path) -> u64 {
    std::fs::metadata(path).map_or(u64::MAX, |m| m.len().saturating_mul(MAX_EXPANSION).saturating_add(1 << 20))
}

/// Reads a compound table back as named columns (floats and integers), in field order. The table's
/// declared size must be at most `limit` bytes ([`read_limit`]) and its fields must lie inside its
/// rows: a damaged or crafted declaration is an error, not an allocation or a panic.
pub fn decode(dataset: &Dataset, limit: u64) -> Result<Vec<(String, ColumnData)>, LayoutError> {
    let Datatype::Compound { size, members } = dataset.datatype()? else {
        return Err(LayoutError::inconsistent("not a compound (table) dataset"));
    };
    let shape = dataset.shape()?;
    let declared = shape.iter().try_fold(u64::from(size), |bytes, &n| bytes.checked_mul(n));
    if declared.is_none_or(|bytes| bytes > limit) {
        return Err(LayoutError::too_large(format!("{shape:?} rows of {size} bytes")));
    }
    if size == 0 {
        return Err(LayoutError::inconsistent("declares rows of 0 bytes"));
    }
    if let Some(m) = members.iter().find(|m| m.byte_offset as usize + m.datatype.type_size() as usize > size as usize) {
        return Err(LayoutError::inconsistent(format!("field `{}` lies outside its {size}-byte rows", m.name)));
    }
    let raw = dataset.read_raw()?;
    let rows: Vec<&[u8]> = raw.chunks_exact(size as usize).collect();
    members
        .iter()
        .map(|m| {
            let at = m.byte_offset as usize;
            let bytes = |row: &[u8], n: usize| -> Vec<u8> { row[at..at + n].to_vec() };
            let data = match (&m.datatype, m.datatype.type_size()) {
                (Datatype::FloatingPoint { .. }, 8) => ColumnData::Float(
                    rows.iter().map(|r| f64::from_le_bytes(bytes(r, 8).try_into().expect("8 bytes"))).collect(),
                ),
                (Datatype::FixedPoint { .. }, 4) => ColumnData::Int(
                    rows.iter()
                        .map(|r| i64::from(u32::from_le_bytes(bytes(r, 4).try_into().expect("4 bytes"))))
                        .collect(),
                ),
                (Datatype::FixedPoint { .. }, 8) => ColumnData::Int(
                    rows.iter().map(|r| i64::from_le_bytes(bytes(r, 8).try_into().expect("8 bytes"))).collect(),
                ),
                (Datatype::FixedPoint { .. }, 1) => ColumnData::Bool(rows.iter().map(|r| r[at] != 0).collect()),
                (Datatype::String { .. }, n) => ColumnData::Text(
                    rows.iter()
                        .map(|r| {
                            let text = &r[at..at + n as usize];
                            let end = text.iter().position(|&b| b == 0).unwrap_or(text.len());
                            String::from_utf8_lossy(&text[..end]).into_owned()
                        })
                        .collect(),
                ),
                _ => return Err(LayoutError::inconsistent(format!("field `{}` has an unsupported type", m.name))),
            };
            Ok((m.name.clone(), data))
        })
        .collect()
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_table_declaring_more_than_the_limit_is_refused_before_it_is_read() {
        let path = std::env::temp_dir().join(format!("demsweep-compound-{}.h5", std::process::id()));
        let values: Vec<f64> = (0..100).map(f64::from).collect();
        let (datatype, bytes, rows) = encode(&[("x", Field::F64(&values)), ("y", Field::F64(&values))]);
        let mut builder = hdf5_pure::FileBuilder::new();
        builder.create_dataset("table").with_compound_data(datatype, bytes, rows);
        builder.write(&path).unwrap();
        let file = hdf5_pure::File::open(&path).unwrap();
        let dataset = file.dataset("table").unwrap();
        let refused = decode(&dataset, 100 * 16 - 1).unwrap_err().to_string();
        assert!(refused.contains("[100] rows of 16 bytes"), "{refused}");
        let columns = decode(&dataset, read_limit(&path)).unwrap();
        assert_eq!(columns[1], ("y".to_string(), ColumnData::Float(values)));
        std::fs::remove_file(&path).unwrap();
    }
}

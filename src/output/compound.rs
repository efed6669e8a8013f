//! Tables stored as one compound dataset (one named field per column): a single HDF5 object per
//! table keeps the object count per run small, and h5py reads a column as `dataset["name"]`.

use hdf5_pure::{CompoundTypeBuilder, Dataset, Datatype};

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
}

impl Field<'_> {
    fn len(&self) -> usize {
        match self {
            Field::F64(v) => v.len(),
            Field::U32(v) => v.len(),
            Field::I64(v) => v.len(),
            Field::Bool(v) => v.len(),
        }
    }
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
            }
        }
    }
    (datatype, bytes, rows as u64)
}

/// Reads a compound table back as named columns (floats and integers), in field order.
pub fn decode(dataset: &Dataset) -> Result<Vec<(String, ColumnData)>, String> {
    let Datatype::Compound { size, members } = dataset.datatype().map_err(|e| e.to_string())? else {
        return Err("not a compound (table) dataset".into());
    };
    let raw = dataset.read_raw().map_err(|e| e.to_string())?;
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
                _ => return Err(format!("field `{}` has an unsupported type", m.name)),
            };
            Ok((m.name.clone(), data))
        })
        .collect()
}

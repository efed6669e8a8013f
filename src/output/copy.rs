//! Copying a run group from one results file into another one run at a time: the group is read from
//! the (streaming) source into memory, then staged in the destination, so that a merge holds a few
//! runs in memory, never a whole shard. Datasets keep their datatype, shape, chunking, filters and
//! attributes; their data is decoded and encoded again.

use hdf5_pure::{AttrValue, DatasetBuilder, Datatype, Group, StagedGroup};

use super::layout_error::LayoutError;

/// HDF5's registered filter identifiers of deflate, shuffle and Fletcher-32.
const FILTER_DEFLATE: u16 = 1;
const FILTER_SHUFFLE: u16 = 2;
const FILTER_FLETCHER32: u16 = 3;

/// A group read from a results file: its attributes, datasets and subgroups, sorted by name.
pub struct GroupCopy {
    attrs: Vec<(String, AttrValue)>,
    datasets: Vec<DatasetCopy>,
    groups: Vec<(String, GroupCopy)>,
}

/// A dataset read from a results file.
struct DatasetCopy {
    name: String,
    datatype: Datatype,
    shape: Vec<u64>,
    bytes: Vec<u8>,
    chunks: Option<Vec<u64>>,
    /// Shuffle, then deflate at this level, then a Fletcher-32 checksum, as the source had them.
    shuffle: bool,
    deflate: Option<u32>,
    fletcher32: bool,
    attrs: Vec<(String, AttrValue)>,
}

impl GroupCopy {
    /// Reads `group` and everything under it (checksums verified); a filter other than shuffle,
    /// deflate and Fletcher-32 is refused.
    pub fn read(group: &Group) -> Result<Self, LayoutError> {
        let mut datasets = Vec::new();
        for (name, dataset) in group.iter_datasets()? {
            let (mut shuffle, mut deflate, mut fletcher32) = (false, None, false);
            for filter in dataset.filter_pipeline() {
                match filter.id {
                    FILTER_SHUFFLE => shuffle = true,
                    FILTER_FLETCHER32 => fletcher32 = true,
                    FILTER_DEFLATE => deflate = Some(filter.client_data.first().copied().unwrap_or(1)),
                    other => {
                        let refused = LayoutError::inconsistent(format!("filter {other} cannot be copied"));
                        return Err(refused.within(name));
                    }
                }
            }
            datasets.push(DatasetCopy {
                datatype: dataset.datatype()?,
                shape: dataset.shape()?,
                bytes: dataset.read_raw().map_err(|e| LayoutError::from(e).within(&name))?,
                chunks: dataset.chunk_shape()?,
                shuffle,
                deflate,
                fletcher32,
                attrs: sorted(dataset.attrs()?),
                name,
            });
        }
        datasets.sort_by(|a, b| a.name.cmp(&b.name));
        let mut groups = Vec::new();
        for (name, child) in group.iter_groups()? {
            groups.push((name, Self::read(&child)?));
        }
        groups.sort_by(|a, b| a.0.cmp(&b.0));
        Ok(Self { attrs: sorted(group.attrs()?), datasets, groups })
    }

    /// Bytes of dataset data held (the decoded size).
    pub fn data_bytes(&self) -> usize {
        let own: usize = self.datasets.iter().map(|d| d.bytes.len()).sum();
        own + self.groups.iter().map(|(_, g)| g.data_bytes()).sum::<usize>()
    }

    /// Stages the copy into `g` (a new, empty group).
    pub fn stage(self, g: &mut StagedGroup<'_>) {
        for (name, value) in self.attrs {
            g.set_attr(&name, value);
        }
        for dataset in self.datasets {
            g.create_dataset(&dataset.name.clone(), |b| dataset.stage(b));
        }
        for (name, group) in self.groups {
            g.create_group_with(&name, |child| group.stage(child));
        }
    }
}

impl DatasetCopy {
    fn stage(self, b: &mut DatasetBuilder) {
        let elements = self.shape.iter().product();
        b.with_raw_data(self.datatype, self.bytes, elements).with_shape(&self.shape);
        if let Some(chunks) = &self.chunks {
            b.with_chunks(chunks);
        }
        if self.shuffle {
            b.with_shuffle();
        }
        if let Some(level) = self.deflate {
            b.with_deflate(level);
        }
        if self.fletcher32 {
            b.with_fletcher32();
        }
        for (name, value) in self.attrs {
            b.set_attr(&name, value);
        }
    }
}

fn sorted(attrs: std::collections::HashMap<String, AttrValue>) -> Vec<(String, AttrValue)> {
    let mut attrs: Vec<(String, AttrValue)> = attrs.into_iter().collect();
    attrs.sort_by(|a, b| a.0.cmp(&b.0));
    attrs
}

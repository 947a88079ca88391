//! A recording's MCAP file: written to `run.mcap.partial`, renamed to `run.mcap` when it
//! finishes, so that an interrupted run leaves no file that looks complete.

use super::topics::{Publish, Topic};
use super::RECORDING_NAME;
use anyhow::{Context, Result};
use std::collections::BTreeMap;
use std::fs::File;
use std::io::BufWriter;
use std::path::{Path, PathBuf};

pub struct McapFile {
    writer: mcap::Writer<BufWriter<File>>,
    partial: PathBuf,
    target: PathBuf,
    /// The channel id of each topic the file holds (by [`Topic::index`]).
    channels: [Option<u16>; Topic::COUNT],
    sequence: u32,
}

impl McapFile {
    /// Starts `run.mcap.partial` in `dir`, with one JSON channel per topic of `topics`.
    pub fn create(dir: &Path, topics: &[Topic]) -> Result<Self> {
        let partial = dir.join(format!("{RECORDING_NAME}.partial"));
        let file =
            File::create(&partial).with_context(|| format!("creating {}", partial.display()))?;
        let mut writer = mcap::Writer::new(BufWriter::new(file))?;
        let no_metadata = BTreeMap::new();
        let mut channels = [None; Topic::COUNT];
        for &topic in topics {
            let schema =
                writer.add_schema(topic.schema_name(), "jsonschema", topic.schema().as_bytes())?;
            channels[topic.index()] =
                Some(writer.add_channel(schema, topic.name(), "json", &no_metadata)?);
        }
        Ok(Self {
            writer,
            target: dir.join(RECORDING_NAME),
            partial,
            channels,
            sequence: 0,
        })
    }
}

impl Publish for McapFile {
    fn publish(&mut self, topic: Topic, t: f64, json: Vec<u8>) -> Result<()> {
        let time = (t.max(0.0) * 1e9).round() as u64;
        let Some(channel_id) = self.channels[topic.index()] else {
            anyhow::bail!("{}: not a topic of this recording", topic.name());
        };
        let header = mcap::records::MessageHeader {
            channel_id,
            sequence: self.sequence,
            log_time: time,
            publish_time: time,
        };
        self.sequence = self.sequence.wrapping_add(1);
        self.writer.write_to_known_channel(&header, &json)?;
        Ok(())
    }

    fn finish(mut self: Box<Self>) -> Result<Option<PathBuf>> {
        self.writer.finish()?;
        let Self {
            writer,
            partial,
            target,
            ..
        } = *self;
        drop(writer);
        std::fs::rename(&partial, &target)
            .with_context(|| format!("writing {}", target.display()))?;
        Ok(Some(target))
    }
}

//! Multi-channel `f32` OpenEXR files: the one place natura touches the `exr` crate.
//!
//! Written files are lossless (ZIP, 16 scanlines per block), carry the
//! channels given, any text attributes, and a `naturaChecksum` attribute (FNV-1a
//! over the channel data) that [`read_exr`] verifies when present, so a file
//! corrupted after writing is refused rather than silently misread.

use std::io::{BufReader, Read, Seek, Write};
use std::path::Path;

use exr::prelude::*;

use crate::error::{CoreError, Result};
use crate::grid2::checked_len;
use crate::io::{WriteError, write_atomic};

const CHECKSUM_KEY: &str = "naturaChecksum";
/// The checksum of the other text attributes (a height map's cell size and
/// range live there): a flipped digit in them changed the field silently.
/// Files written before it existed carry none and are read as before.
const ATTRIBUTES_CHECKSUM_KEY: &str = "naturaAttributesChecksum";

/// FNV-1a over the text attributes in key order, the two checksums left out.
fn attributes_checksum<'a>(attributes: impl Iterator<Item = (&'a str, &'a str)>) -> String {
    let mut sorted: Vec<_> = attributes
        .filter(|(k, _)| *k != CHECKSUM_KEY && *k != ATTRIBUTES_CHECKSUM_KEY)
        .collect();
    sorted.sort_unstable();
    fnv1a_hex(
        sorted
            .into_iter()
            .flat_map(|(k, v)| k.bytes().chain([0]).chain(v.bytes()).chain([0])),
    )
}

/// [`checksum`](crate::io::checksum) of `bytes`, as 16 hexadecimal digits.
fn fnv1a_hex(bytes: impl IntoIterator<Item = u8>) -> String {
    format!("{:016x}", crate::io::checksum(bytes))
}

/// The channels and text attributes of one EXR layer, all as `f32`.
#[derive(Clone, Debug, PartialEq)]
pub struct ExrChannels {
    /// Pixels per row.
    pub width: usize,
    /// Rows.
    pub height: usize,
    /// `(name, row-major samples)`, each `width·height` long.
    pub channels: Vec<(String, Vec<f32>)>,
    /// Text attributes of the layer, `(key, value)`.
    pub attributes: Vec<(String, String)>,
}

impl ExrChannels {
    /// The samples of the channel called `name`, if present.
    #[must_use]
    pub fn channel(&self, name: &str) -> Option<&[f32]> {
        self.channels
            .iter()
            .find(|(n, _)| n == name)
            .map(|(_, v)| v.as_slice())
    }

    /// The text attribute `key`, if present.
    #[must_use]
    pub fn attribute(&self, key: &str) -> Option<&str> {
        self.attributes
            .iter()
            .find(|(k, _)| k == key)
            .map(|(_, v)| v.as_str())
    }
}

/// FNV-1a over the channels in name order (EXR stores channels sorted by name,
/// so the order given to the writer is not the order read back).
fn checksum<'a>(channels: impl Iterator<Item = (&'a str, &'a [f32])>) -> String {
    let mut sorted: Vec<_> = channels.collect();
    sorted.sort_by(|a, b| a.0.cmp(b.0));
    fnv1a_hex(sorted.into_iter().flat_map(|(name, data)| {
        name.bytes()
            .chain([0])
            .chain(data.iter().flat_map(|v| v.to_bits().to_le_bytes()))
    }))
}

/// Writes `channels` (each `width·height` row-major `f32` samples) and text
/// `attributes` to `path` as a lossless EXR, atomically.
///
/// Fails on a zero or oversize resolution, a channel of the wrong length, or
/// an I/O error, naming the file.
///
/// # Errors
///
/// Returns [`CoreError::Io`] naming the file if it cannot be written (a missing or
/// read-only folder, a directory in the way), and [`CoreError::Format`]
/// if the encoder refuses the data. Nothing is left half-written.
/// Channels of the wrong length are [`CoreError::SizeMismatch`].
pub fn write_exr(
    path: impl AsRef<Path>,
    width: usize,
    height: usize,
    channels: &[(&str, &[f32])],
    attributes: &[(&str, &str)],
) -> Result<()> {
    write_exr_impl(path.as_ref(), width, height, channels, attributes)
}

/// The body of [`write_exr`]: not generic, so it is compiled once, here, and not again in every
/// crate that calls it.
fn write_exr_impl(
    path: &Path,
    width: usize,
    height: usize,
    channels: &[(&str, &[f32])],
    attributes: &[(&str, &str)],
) -> Result<()> {
    let len = checked_len::<f32>(&[width, height, channels.len().max(1)])? / channels.len().max(1);
    if channels.is_empty() {
        return Err(CoreError::format(path, "no channels to write"));
    }
    for (name, data) in channels {
        if data.len() != len {
            return Err(CoreError::SizeMismatch {
                expected: format!("channel `{name}` with {width} × {height} = {len} samples"),
                actual: format!("{} samples", data.len()),
            });
        }
    }
    let list: SmallVec<[AnyChannel<FlatSamples>; 4]> = channels
        .iter()
        .map(|(name, data)| AnyChannel::new(*name, FlatSamples::F32(data.to_vec())))
        .collect();
    let mut attrs = LayerAttributes::default();
    for (k, v) in attributes {
        attrs
            .other
            .insert(Text::from(*k), AttributeValue::Text(Text::from(*v)));
    }
    let sum = checksum(channels.iter().map(|(n, d)| (*n, *d)));
    attrs.other.insert(
        Text::from(ATTRIBUTES_CHECKSUM_KEY),
        AttributeValue::Text(Text::from(
            attributes_checksum(attributes.iter().map(|(k, v)| (*k, *v))).as_str(),
        )),
    );
    attrs.other.insert(
        Text::from(CHECKSUM_KEY),
        AttributeValue::Text(Text::from(sum.as_str())),
    );
    let layer = Layer::new(
        (width, height),
        attrs,
        Encoding::SMALL_LOSSLESS,
        AnyChannels::sort(list),
    );
    let image = Image::from_layer(layer);
    write_atomic(path, |w| {
        // Encoded in memory first: the encoder writes the header's custom
        // attributes in the order of a randomly seeded hash map, so the
        // same image would give different bytes from run to run. Sorting
        // the header's attributes by name makes the file a function of its
        // contents (the header keeps its length, so the offsets stay valid).
        let mut bytes = std::io::Cursor::new(Vec::new());
        image.write().to_buffered(&mut bytes).map_err(|e| match e {
            exr::error::Error::Io(e) => WriteError::Io(e),
            other => WriteError::Encode(other.to_string()),
        })?;
        let mut bytes = bytes.into_inner();
        sort_header_attributes(&mut bytes).ok_or_else(|| {
            WriteError::Encode("the encoder wrote a header this writer cannot read".into())
        })?;
        w.write_all(&bytes)?;
        Ok(())
    })
}

/// Sorts the attributes of a single-part EXR header by name, in place.
///
/// An OpenEXR header (OpenEXR file layout, "Header") is a list of
/// attributes — a null-terminated name, a null-terminated type name, a
/// little-endian `i32` size and that many bytes of value — closed by an
/// empty name. Their order carries no meaning, and the total length is
/// unchanged, so the offset table after the header stays valid. Returns
/// `None` (leaving `bytes` unchanged) for anything but a single-part file
/// whose header parses.
fn sort_header_attributes(bytes: &mut [u8]) -> Option<()> {
    const MAGIC: [u8; 4] = [0x76, 0x2f, 0x31, 0x01];
    const MULTIPART: u8 = 0x10; // bit 12 of the version field
    if bytes.len() < 8 || bytes[..4] != MAGIC || bytes[5] & MULTIPART != 0 {
        return None;
    }
    let string_end = |from: usize| -> Option<usize> {
        let n = bytes.get(from..)?.iter().position(|&b| b == 0)?;
        Some(from + n)
    };
    let mut spans: Vec<(usize, usize, usize)> = Vec::new(); // (start, name end, end)
    let mut at = 8;
    loop {
        let name_end = string_end(at)?;
        if name_end == at {
            break;
        }
        let type_end = string_end(name_end + 1)?;
        let size_at = type_end + 1;
        let size = i32::from_le_bytes(bytes.get(size_at..size_at + 4)?.try_into().ok()?);
        let end = size_at
            .checked_add(4)?
            .checked_add(usize::try_from(size).ok()?)?;
        if end > bytes.len() {
            return None;
        }
        spans.push((at, name_end, end));
        at = end;
    }
    let header = 8..at;
    let mut sorted = Vec::with_capacity(header.len());
    spans.sort_by(|a, b| bytes[a.0..a.1].cmp(&bytes[b.0..b.1]));
    for &(start, _, end) in &spans {
        sorted.extend_from_slice(&bytes[start..end]);
    }
    bytes[header].copy_from_slice(&sorted);
    Some(())
}

/// Reads the first layer of an EXR file at its full resolution, converting
/// every channel to `f32`.
///
/// Corrupt, truncated or absurdly sized files give [`CoreError::Format`]
/// naming the file and the problem; a file whose `naturaChecksum` does not
/// match its pixels is refused. The header's resolution is checked against
/// [`crate::MAX_GRID_BYTES`] before any pixel memory is allocated.
///
/// # Errors
///
/// Returns [`CoreError::Io`] naming the file if it cannot be read, and
/// [`CoreError::Format`] if it is truncated, corrupt or of an
/// unsupported layout, or if its size exceeds the memory cap.
pub fn read_exr(path: impl AsRef<Path>) -> Result<ExrChannels> {
    read_exr_impl(path.as_ref())
}

/// The body of [`read_exr`]: not generic, so it is compiled once, here, and not again in every
/// crate that calls it.
fn read_exr_impl(path: &Path) -> Result<ExrChannels> {
    let file = std::fs::File::open(path).map_err(|e| CoreError::Io {
        path: path.into(),
        source: e,
    })?;
    read_exr_from(BufReader::new(file), path)
}

/// As [`read_exr`], from any seekable reader; `name` labels errors.
///
/// # Errors
///
/// Returns [`CoreError::Io`] naming the file if it cannot be read, and
/// [`CoreError::Format`] if it is truncated, corrupt or of an
/// unsupported layout, or if its size exceeds the memory cap.
pub fn read_exr_from(mut reader: impl Read + Seek, name: &Path) -> Result<ExrChannels> {
    let bad = |m: String| CoreError::format(name, m);
    let meta = MetaData::read_from_buffered(&mut reader, false)
        .map_err(|e| bad(format!("not a readable EXR file: {e}")))?;
    let header = meta
        .headers
        .first()
        .ok_or_else(|| bad("EXR file has no layers".into()))?;
    let (w, h) = (header.layer_size.width(), header.layer_size.height());
    let nch = header.channels.list.len();
    checked_len::<f32>(&[w, h, nch.max(1)]).map_err(|e| bad(format!("EXR header: {e}")))?;
    reader.rewind().map_err(|e| CoreError::Io {
        path: name.into(),
        source: e,
    })?;

    let image = read()
        .no_deep_data()
        .largest_resolution_level()
        .all_channels()
        .first_valid_layer()
        .all_attributes()
        .non_parallel()
        .from_buffered(reader)
        .map_err(|e| bad(format!("corrupt or truncated EXR: {e}")))?;

    let layer = &image.layer_data;
    let (w, h) = (layer.size.width(), layer.size.height());
    let mut channels = Vec::with_capacity(layer.channel_data.list.len());
    for ch in &layer.channel_data.list {
        let values: Vec<f32> = ch.sample_data.values_as_f32().collect();
        if values.len() != w * h {
            return Err(bad(format!(
                "channel `{}` has {} samples, expected {}",
                ch.name,
                values.len(),
                w * h
            )));
        }
        channels.push((ch.name.to_string(), values));
    }
    let mut attributes = Vec::new();
    for (k, v) in layer
        .attributes
        .other
        .iter()
        .chain(image.attributes.other.iter())
    {
        if let AttributeValue::Text(t) = v {
            attributes.push((k.to_string(), t.to_string()));
        }
    }
    attributes.sort();
    let out = ExrChannels {
        width: w,
        height: h,
        channels,
        attributes,
    };
    if let Some(expected) = out.attribute(CHECKSUM_KEY) {
        let got = checksum(out.channels.iter().map(|(n, d)| (n.as_str(), d.as_slice())));
        if got != expected {
            return Err(bad(format!(
                "checksum mismatch (stored {expected}, data gives {got}): file is corrupt"
            )));
        }
    }
    if let Some(expected) = out.attribute(ATTRIBUTES_CHECKSUM_KEY) {
        let got = attributes_checksum(out.attributes.iter().map(|(k, v)| (k.as_str(), v.as_str())));
        if got != expected {
            return Err(bad(format!(
                "attribute checksum mismatch (stored {expected}, attributes give {got}): file is corrupt"
            )));
        }
    }
    Ok(out)
}

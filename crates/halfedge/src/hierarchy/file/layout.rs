//! The frame of a hierarchy file: the header (magic, format version, section table, the
//! header's CRC-32) and the sections, each followed by its own CRC-32.

use std::path::Path;

use super::bytes::{format_error, get_u32, get_u64};
use super::{FORMAT_VERSION, OLDEST_READABLE_VERSION};
use crate::error::Result;

/// The first eight bytes of every hierarchy file (after PNG's: a high byte, the name,
/// and the line endings and end-of-file character that text-mode transfers mangle).
pub(super) const MAGIC: [u8; 8] = *b"\x89MRH\r\n\x1a\n";

/// The sections of a file of this version, in file order.
pub(super) const SECTIONS: [&str; 8] = [
    "META", "MESH", "LABL", "RECS", "PLAC", "DETL", "MARK", "REST",
];

/// Bytes of one entry of the section table: tag, flags, offset, length.
const ENTRY: usize = 4 + 4 + 8 + 8;

/// Bytes before the table: magic, version, section count.
const PREAMBLE: usize = 8 + 4 + 4;

/// Bytes of the header: preamble, table, CRC-32.
pub(super) const HEADER: usize = PREAMBLE + SECTIONS.len() * ENTRY + 4;

/// The header of a file whose sections have these lengths (in [`SECTIONS`] order).
pub(super) fn header(lengths: &[u64; SECTIONS.len()]) -> Vec<u8> {
    let mut out = Vec::with_capacity(HEADER);
    out.extend_from_slice(&MAGIC);
    out.extend_from_slice(&FORMAT_VERSION.to_le_bytes());
    out.extend_from_slice(&(SECTIONS.len() as u32).to_le_bytes());
    let mut offset = HEADER as u64;
    for (tag, &length) in SECTIONS.iter().zip(lengths) {
        out.extend_from_slice(tag.as_bytes());
        out.extend_from_slice(&0u32.to_le_bytes());
        out.extend_from_slice(&offset.to_le_bytes());
        out.extend_from_slice(&length.to_le_bytes());
        offset += length + 4;
    }
    let crc = crc32fast::hash(&out);
    out.extend_from_slice(&crc.to_le_bytes());
    out
}

/// A section found in a file: its tag, where its payload starts, its bytes and the
/// CRC-32 stored after them.
#[derive(Clone, Copy, Debug)]
pub(super) struct Section<'a> {
    pub(super) tag: &'static str,
    pub(super) offset: usize,
    pub(super) bytes: &'a [u8],
    crc: u32,
}

impl Section<'_> {
    /// Checks the section's bytes against its CRC-32.
    ///
    /// # Errors
    /// [`crate::Error::Format`] naming `path` and the section.
    pub(super) fn verify(&self, path: &Path) -> Result<()> {
        let computed = crc32fast::hash(self.bytes);
        if self.crc != computed {
            return Err(format_error(
                path,
                format!(
                    "section {}: CRC-32 {:08x} stored, {computed:08x} computed (the section \
                     is corrupt)",
                    self.tag, self.crc
                ),
            ));
        }
        Ok(())
    }
}

/// The sections of `file` in [`SECTIONS`] order, after checking the magic, the format
/// version, the section table (every section of this version, in order, end to end,
/// the last ending where the file ends) and the header's CRC; each section's own CRC is
/// checked by [`Section::verify`].
///
/// # Errors
/// [`crate::Error::Format`] naming `path` and what is wrong.
pub(super) fn sections<'a>(file: &'a [u8], path: &Path) -> Result<[Section<'a>; SECTIONS.len()]> {
    let entries = table(file, file.len() as u64, path)?;
    Ok(entries.map(|e| Section {
        tag: e.tag,
        offset: e.offset,
        bytes: &file[e.offset..e.offset + e.length],
        crc: get_u32(&file[e.offset + e.length..]),
    }))
}

/// An entry of the section table: the section's tag, where its payload starts and its
/// length (its CRC-32 follows it).
#[derive(Clone, Copy, Debug)]
pub(super) struct Entry {
    pub(super) tag: &'static str,
    pub(super) offset: usize,
    pub(super) length: usize,
}

/// The section table of a file of `file_len` bytes whose first bytes are `head` (all of
/// the header, or the whole file when it is shorter), checked as [`sections`] says.
///
/// # Errors
/// [`crate::Error::Format`] naming `path` and what is wrong.
pub(super) fn table(head: &[u8], file_len: u64, path: &Path) -> Result<[Entry; SECTIONS.len()]> {
    let file = head;
    let fail = |message: String| Err(format_error(path, message));
    if file.len() < PREAMBLE {
        return fail(format!(
            "{file_len} bytes: too short for a hierarchy file header ({HEADER} bytes)"
        ));
    }
    if file[..8] != MAGIC {
        return fail("not a hierarchy file (.mrh): the first 8 bytes are not its magic".into());
    }
    let version = get_u32(&file[8..]);
    if !(OLDEST_READABLE_VERSION..=FORMAT_VERSION).contains(&version) {
        return fail(format!(
            "hierarchy file format version {version}; this library reads versions \
             {OLDEST_READABLE_VERSION} to {FORMAT_VERSION} (see docs/guide/hierarchy-file.md: \
             save it again with the library that wrote it, or rebuild the hierarchy)"
        ));
    }
    let count = get_u32(&file[12..]);
    if count as usize != SECTIONS.len() {
        return fail(format!(
            "header: {count} sections announced, version {version} has {}",
            SECTIONS.len()
        ));
    }
    if file.len() < HEADER {
        return fail(format!(
            "{file_len} bytes: truncated in the header ({HEADER} bytes)"
        ));
    }
    let stored = get_u32(&file[HEADER - 4..]);
    let computed = crc32fast::hash(&file[..HEADER - 4]);
    if stored != computed {
        return fail(format!(
            "header: CRC-32 {stored:08x} stored, {computed:08x} computed (the header is corrupt)"
        ));
    }
    let mut expected = HEADER as u64;
    let mut out = [Entry {
        tag: "",
        offset: 0,
        length: 0,
    }; SECTIONS.len()];
    for (k, tag) in SECTIONS.iter().enumerate() {
        let entry = &file[PREAMBLE + k * ENTRY..PREAMBLE + (k + 1) * ENTRY];
        let found = &entry[..4];
        if found != tag.as_bytes() {
            return fail(format!(
                "section table entry {k}: tag {:?}, expected {tag}",
                String::from_utf8_lossy(found)
            ));
        }
        let flags = get_u32(&entry[4..]);
        let offset = get_u64(&entry[8..]);
        let length = get_u64(&entry[16..]);
        if flags != 0 {
            return fail(format!("section {tag}: unknown flags {flags:#x}"));
        }
        if offset != expected {
            return fail(format!(
                "section {tag}: starts at byte {offset}, expected {expected}"
            ));
        }
        let end = offset
            .checked_add(length)
            .and_then(|e| e.checked_add(4))
            .filter(|&e| e <= file_len);
        let Some(end) = end else {
            return fail(format!(
                "section {tag}: {length} bytes at byte {offset} run past the end of the \
                 file ({file_len} bytes): the file is truncated"
            ));
        };
        out[k] = Entry {
            tag,
            offset: offset as usize,
            length: length as usize,
        };
        expected = end;
    }
    if expected != file_len {
        return fail(format!(
            "{} bytes after the last section",
            file_len - expected
        ));
    }
    Ok(out)
}

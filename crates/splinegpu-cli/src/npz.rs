//! A streaming NPZ writer: a zip archive of uncompressed `.npy` arrays that numpy.load reads,
//! written front to back without seeking (so standard output works too).
//!
//! Each entry's sizes are known before its data (the caller declares the array's shape); its
//! CRC-32 follows the data in a data descriptor (general-purpose flag bit 3). Every entry and
//! the end of the archive carry zip64 records, so arrays and archives past 4 GiB are fine.

use std::io::{self, Write};

use crate::spill::Spill;

/// The `.npy` element types written here.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Dtype {
    /// Little-endian float32, `<f4`.
    F32,
    /// Little-endian float64, `<f8`.
    F64,
    /// Little-endian int64, `<i8`.
    I64,
    /// One byte per boolean, `|b1`.
    Bool,
}

impl Dtype {
    /// The type of values of `F`: [`Dtype::F32`] or [`Dtype::F64`].
    #[must_use]
    pub fn of<F: splinegpu::SampleFloat>() -> Self {
        if F::NAME == "f32" {
            Dtype::F32
        } else {
            Dtype::F64
        }
    }

    fn descr(self) -> &'static str {
        match self {
            Dtype::F32 => "<f4",
            Dtype::F64 => "<f8",
            Dtype::I64 => "<i8",
            Dtype::Bool => "|b1",
        }
    }

    /// Bytes per element.
    #[must_use]
    pub fn size(self) -> u64 {
        match self {
            Dtype::Bool => 1,
            Dtype::F32 => 4,
            Dtype::F64 | Dtype::I64 => 8,
        }
    }
}

/// An archive being written to `out`.
#[derive(Debug)]
pub struct NpzWriter<W: Write> {
    out: W,
    /// Bytes written so far: the next local header's offset.
    written: u64,
    entries: Vec<Entry>,
    open: Option<Open>,
}

#[derive(Debug)]
struct Entry {
    name: String,
    offset: u64,
    size: u64,
    crc: u32,
}

#[derive(Debug)]
struct Open {
    entry: Entry,
    hasher: crc32fast::Hasher,
    remaining: u64,
}

/// The date field of every entry: 1980-01-01, the zip epoch.
const DOS_DATE: u16 = 0x0021;

impl<W: Write> NpzWriter<W> {
    /// An empty archive on `out`.
    pub fn new(out: W) -> Self {
        Self {
            out,
            written: 0,
            entries: Vec::new(),
            open: None,
        }
    }

    /// Starts the array `name` (".npy" is appended) of `shape` and `dtype`; its
    /// `shape.iter().product()` elements must follow through [`NpzWriter::write`].
    ///
    /// # Errors
    /// Any I/O error.
    pub fn begin(&mut self, name: &str, dtype: Dtype, shape: &[u64]) -> io::Result<()> {
        debug_assert!(self.open.is_none(), "the previous array is not finished");
        let header = npy_header(dtype, shape);
        let elements: u64 = shape.iter().product();
        let size = header.len() as u64 + elements * dtype.size();
        let name = format!("{name}.npy");
        let offset = self.written;
        let mut local = Vec::with_capacity(30 + name.len() + 20);
        local.extend_from_slice(&0x0403_4b50u32.to_le_bytes());
        local.extend_from_slice(&45u16.to_le_bytes()); // version needed: zip64
        local.extend_from_slice(&0x0008u16.to_le_bytes()); // sizes and CRC in a data descriptor
        local.extend_from_slice(&0u16.to_le_bytes()); // stored
        local.extend_from_slice(&0u16.to_le_bytes()); // time
        local.extend_from_slice(&DOS_DATE.to_le_bytes());
        local.extend_from_slice(&0u32.to_le_bytes()); // CRC: in the descriptor
        local.extend_from_slice(&u32::MAX.to_le_bytes()); // sizes: in the zip64 field
        local.extend_from_slice(&u32::MAX.to_le_bytes());
        local.extend_from_slice(&(name.len() as u16).to_le_bytes());
        local.extend_from_slice(&20u16.to_le_bytes());
        local.extend_from_slice(name.as_bytes());
        local.extend_from_slice(&0x0001u16.to_le_bytes()); // zip64 extra field
        local.extend_from_slice(&16u16.to_le_bytes());
        local.extend_from_slice(&size.to_le_bytes());
        local.extend_from_slice(&size.to_le_bytes());
        self.raw(&local)?;
        let mut open = Open {
            entry: Entry {
                name,
                offset,
                size,
                crc: 0,
            },
            hasher: crc32fast::Hasher::new(),
            remaining: size,
        };
        open.hasher.update(&header);
        open.remaining -= header.len() as u64;
        self.open = Some(open);
        self.raw(&header)
    }

    /// Appends little-endian element bytes to the open array.
    ///
    /// # Errors
    /// Any I/O error; more bytes than the array declared.
    pub fn write(&mut self, bytes: &[u8]) -> io::Result<()> {
        let open = self.open.as_mut().expect("begin() opens an array first");
        if bytes.len() as u64 > open.remaining {
            return Err(io::Error::other(format!(
                "{}: more data than its shape",
                open.entry.name
            )));
        }
        open.remaining -= bytes.len() as u64;
        open.hasher.update(bytes);
        self.raw(bytes)
    }

    /// Finishes the open array.
    ///
    /// # Errors
    /// Any I/O error; fewer bytes than the array declared.
    pub fn end(&mut self) -> io::Result<()> {
        let open = self.open.take().expect("begin() opens an array first");
        if open.remaining != 0 {
            return Err(io::Error::other(format!(
                "{}: {} bytes short",
                open.entry.name, open.remaining
            )));
        }
        let mut entry = open.entry;
        entry.crc = open.hasher.finalize();
        let mut descriptor = Vec::with_capacity(24);
        descriptor.extend_from_slice(&0x0807_4b50u32.to_le_bytes());
        descriptor.extend_from_slice(&entry.crc.to_le_bytes());
        descriptor.extend_from_slice(&entry.size.to_le_bytes());
        descriptor.extend_from_slice(&entry.size.to_le_bytes());
        self.raw(&descriptor)?;
        self.entries.push(entry);
        Ok(())
    }

    /// One whole array whose data waited in `waiting` (emptied as it is written).
    ///
    /// # Errors
    /// Any I/O error; a spill that does not hold the array's bytes.
    pub fn array_from(
        &mut self,
        name: &str,
        dtype: Dtype,
        shape: &[u64],
        waiting: &mut Spill,
    ) -> io::Result<()> {
        self.begin(name, dtype, shape)?;
        waiting.drain(&mut |bytes| self.write(bytes))?;
        self.end()
    }

    /// One whole int64 array of `offsets` (a layout's starts and its total).
    ///
    /// # Errors
    /// Any I/O error.
    pub fn offsets(&mut self, name: &str, offsets: &[u64]) -> io::Result<()> {
        let signed: Vec<i64> = offsets.iter().map(|&o| o as i64).collect();
        self.begin(name, Dtype::I64, &[offsets.len() as u64])?;
        self.write(bytemuck::cast_slice(&signed))?;
        self.end()
    }

    /// Writes the central directory and the zip64 end records, and returns the output.
    ///
    /// # Errors
    /// Any I/O error.
    pub fn finish(mut self) -> io::Result<W> {
        let start = self.written;
        let mut directory = Vec::new();
        for e in &self.entries {
            directory.extend_from_slice(&0x0201_4b50u32.to_le_bytes());
            directory.extend_from_slice(&45u16.to_le_bytes()); // made by
            directory.extend_from_slice(&45u16.to_le_bytes()); // needed
            directory.extend_from_slice(&0x0008u16.to_le_bytes());
            directory.extend_from_slice(&0u16.to_le_bytes());
            directory.extend_from_slice(&0u16.to_le_bytes());
            directory.extend_from_slice(&DOS_DATE.to_le_bytes());
            directory.extend_from_slice(&e.crc.to_le_bytes());
            directory.extend_from_slice(&u32::MAX.to_le_bytes());
            directory.extend_from_slice(&u32::MAX.to_le_bytes());
            directory.extend_from_slice(&(e.name.len() as u16).to_le_bytes());
            directory.extend_from_slice(&28u16.to_le_bytes()); // extra
            directory.extend_from_slice(&0u16.to_le_bytes()); // comment
            directory.extend_from_slice(&0u16.to_le_bytes()); // disk
            directory.extend_from_slice(&0u16.to_le_bytes()); // internal attributes
            directory.extend_from_slice(&0u32.to_le_bytes()); // external attributes
            directory.extend_from_slice(&u32::MAX.to_le_bytes()); // offset: in the zip64 field
            directory.extend_from_slice(e.name.as_bytes());
            directory.extend_from_slice(&0x0001u16.to_le_bytes());
            directory.extend_from_slice(&24u16.to_le_bytes());
            directory.extend_from_slice(&e.size.to_le_bytes());
            directory.extend_from_slice(&e.size.to_le_bytes());
            directory.extend_from_slice(&e.offset.to_le_bytes());
        }
        self.raw(&directory)?;
        let count = self.entries.len() as u64;
        let end64 = self.written;
        let mut tail = Vec::new();
        // zip64 end of central directory record, then its locator.
        tail.extend_from_slice(&0x0606_4b50u32.to_le_bytes());
        tail.extend_from_slice(&44u64.to_le_bytes());
        tail.extend_from_slice(&45u16.to_le_bytes());
        tail.extend_from_slice(&45u16.to_le_bytes());
        tail.extend_from_slice(&0u32.to_le_bytes());
        tail.extend_from_slice(&0u32.to_le_bytes());
        tail.extend_from_slice(&count.to_le_bytes());
        tail.extend_from_slice(&count.to_le_bytes());
        tail.extend_from_slice(&(directory.len() as u64).to_le_bytes());
        tail.extend_from_slice(&start.to_le_bytes());
        tail.extend_from_slice(&0x0706_4b50u32.to_le_bytes());
        tail.extend_from_slice(&0u32.to_le_bytes());
        tail.extend_from_slice(&end64.to_le_bytes());
        tail.extend_from_slice(&1u32.to_le_bytes());
        // The classic end record, pointing to the zip64 one.
        tail.extend_from_slice(&0x0605_4b50u32.to_le_bytes());
        tail.extend_from_slice(&0u16.to_le_bytes());
        tail.extend_from_slice(&0u16.to_le_bytes());
        tail.extend_from_slice(&u16::MAX.to_le_bytes());
        tail.extend_from_slice(&u16::MAX.to_le_bytes());
        tail.extend_from_slice(&u32::MAX.to_le_bytes());
        tail.extend_from_slice(&u32::MAX.to_le_bytes());
        tail.extend_from_slice(&0u16.to_le_bytes());
        self.raw(&tail)?;
        Ok(self.out)
    }

    fn raw(&mut self, bytes: &[u8]) -> io::Result<()> {
        self.written += bytes.len() as u64;
        self.out.write_all(bytes)
    }
}

/// The `.npy` version 1.0 header of a C-order array, padded so that the data starts at a
/// multiple of 64 bytes.
fn npy_header(dtype: Dtype, shape: &[u64]) -> Vec<u8> {
    let dims: Vec<String> = shape.iter().map(u64::to_string).collect();
    let shape = if dims.len() == 1 {
        format!("({},)", dims[0])
    } else {
        format!("({})", dims.join(", "))
    };
    let mut dict = format!(
        "{{'descr': '{}', 'fortran_order': False, 'shape': {shape}, }}",
        dtype.descr()
    );
    while (10 + dict.len() + 1) % 64 != 0 {
        dict.push(' ');
    }
    dict.push('\n');
    let mut header = b"\x93NUMPY\x01\x00".to_vec();
    header.extend_from_slice(&(dict.len() as u16).to_le_bytes());
    header.extend_from_slice(dict.as_bytes());
    header
}

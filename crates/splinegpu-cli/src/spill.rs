//! Bytes that wait for their turn in an output written front to back (an NPZ array after the
//! one being streamed, a .obj mesh's normals and faces after its positions, a .glb's binary
//! chunk after the JSON that describes it): held in memory up to [`IN_MEMORY`] bytes, then in
//! an unnamed temporary file, so that memory stays bounded however much waits.

use std::fs::File;
use std::io::{self, BufWriter, Read, Seek, Write};

/// Bytes a [`Spill`] holds in memory before it moves them to a temporary file.
pub const IN_MEMORY: usize = 8 << 20;

/// Bytes waiting, in memory or (past [`IN_MEMORY`]) in a temporary file.
#[derive(Debug, Default)]
pub struct Spill {
    memory: Vec<u8>,
    file: Option<BufWriter<File>>,
}

impl Spill {
    /// Nothing waiting.
    #[must_use]
    pub fn new() -> Self {
        Self::default()
    }

    /// Hands every byte waiting to `sink`, in order, in blocks, and empties the spill (it
    /// takes bytes again from its start).
    ///
    /// # Errors
    /// The temporary file's I/O errors, or `sink`'s.
    pub fn drain(&mut self, sink: &mut dyn FnMut(&[u8]) -> io::Result<()>) -> io::Result<()> {
        if let Some(buffered) = &mut self.file {
            buffered.flush()?;
            let file = buffered.get_mut();
            file.rewind()?;
            let mut block = vec![0u8; 1 << 20];
            loop {
                let got = file.read(&mut block)?;
                if got == 0 {
                    break;
                }
                sink(&block[..got])?;
            }
            file.rewind()?;
            file.set_len(0)?;
        }
        sink(&self.memory)?;
        self.memory.clear();
        Ok(())
    }

    /// [`Spill::drain`] into `out`.
    ///
    /// # Errors
    /// As [`Spill::drain`].
    pub fn drain_into(&mut self, out: &mut dyn Write) -> io::Result<()> {
        self.drain(&mut |bytes| out.write_all(bytes))
    }
}

impl Write for Spill {
    fn write(&mut self, bytes: &[u8]) -> io::Result<usize> {
        if self.memory.len() + bytes.len() > IN_MEMORY {
            // Past the limit, what is in memory goes to the file first: order is kept.
            let file = match &mut self.file {
                Some(file) => file,
                None => self
                    .file
                    .insert(BufWriter::with_capacity(1 << 20, tempfile::tempfile()?)),
            };
            file.write_all(&self.memory)?;
            self.memory.clear();
            file.write_all(bytes)?;
        } else {
            self.memory.extend_from_slice(bytes);
        }
        Ok(bytes.len())
    }

    fn flush(&mut self) -> io::Result<()> {
        Ok(())
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Bytes come out in the order they went in, across the move to the file and after a
    /// drain (the spill is used again from its start).
    #[test]
    fn bytes_come_out_in_order_across_the_move_to_a_file() {
        let mut spill = Spill::new();
        let mut want = Vec::new();
        for round in 0..2u8 {
            want.clear();
            for i in 0..40u32 {
                let block = vec![(i as u8) ^ round; 1 << 18];
                spill.write_all(&block).unwrap();
                want.extend_from_slice(&block);
            }
            assert!(spill.file.is_some(), "10 MiB moved to the file");
            let mut got = Vec::new();
            spill.drain_into(&mut got).unwrap();
            assert!(got == want, "round {round}: the bytes differ");
        }
        spill.write_all(b"small").unwrap();
        let mut got = Vec::new();
        spill.drain_into(&mut got).unwrap();
        assert_eq!(got, b"small");
    }
}

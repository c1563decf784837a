//! The compressed forms (.dcd .ecd .scd .tcd .mcd .ncd, .ccc): LZ4 blocks, each
//! preceded by its 2-byte big-endian length, read as one decompressed stream.

use std::io::{self, Read};
use std::sync::atomic::{AtomicU64, Ordering};
use std::sync::Arc;

/// Largest decompressed block accepted. The glider writes blocks of at most
/// 32 KiB (dbdreader's `CHUNKSIZE`); twice that leaves room and still bounds memory.
pub const MAX_BLOCK: usize = 64 * 1024;

/// Why the compressed stream stopped; carried inside an `io::Error`.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct Lz4Problem {
    /// File offset of the block's length field.
    pub block: u64,
    pub truncated: bool,
    pub message: String,
}

impl std::fmt::Display for Lz4Problem {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        write!(f, "{}", self.message)
    }
}

impl std::error::Error for Lz4Problem {}

/// Decompresses block by block; memory is one block.
pub struct Lz4Blocks<R> {
    inner: R,
    compressed: Vec<u8>,
    block: Vec<u8>,
    at: usize,
    /// File offset of the next block's length field.
    file_offset: u64,
    /// File offset of the block now being read, shared with the reader for locations.
    current_block: Arc<AtomicU64>,
}

impl<R: Read> Lz4Blocks<R> {
    pub fn new(inner: R) -> Lz4Blocks<R> {
        Lz4Blocks {
            inner,
            compressed: Vec::new(),
            block: Vec::new(),
            at: 0,
            file_offset: 0,
            current_block: Arc::new(AtomicU64::new(0)),
        }
    }

    /// The file offset of the block the last bytes came from.
    pub fn block_tracker(&self) -> Arc<AtomicU64> {
        Arc::clone(&self.current_block)
    }

    fn problem(&self, truncated: bool, message: String) -> io::Error {
        io::Error::other(Lz4Problem {
            block: self.file_offset,
            truncated,
            message,
        })
    }

    /// Reads the next block; `false` at a clean end of the file.
    fn next_block(&mut self) -> io::Result<bool> {
        let mut length = [0u8; 2];
        let got = read_full(&mut self.inner, &mut length)?;
        if got == 0 {
            return Ok(false);
        }
        if got < 2 {
            return Err(self.problem(true, "the file ends inside an LZ4 block's length".into()));
        }
        let size = u16::from_be_bytes(length) as usize;
        self.compressed.resize(size, 0);
        let got = read_full(&mut self.inner, &mut self.compressed)?;
        if got < size {
            return Err(self.problem(
                true,
                format!("the file ends inside an LZ4 block: {got} of its {size} bytes"),
            ));
        }
        self.block.resize(MAX_BLOCK, 0);
        match lz4_flex::block::decompress_into(&self.compressed, &mut self.block) {
            Ok(written) => self.block.truncate(written),
            Err(error) => {
                return Err(self.problem(false, format!("corrupt LZ4 block ({error})")));
            }
        }
        self.current_block
            .store(self.file_offset, Ordering::Relaxed);
        self.file_offset += 2 + size as u64;
        self.at = 0;
        Ok(true)
    }
}

impl<R: Read> Read for Lz4Blocks<R> {
    fn read(&mut self, buf: &mut [u8]) -> io::Result<usize> {
        while self.at >= self.block.len() {
            if !self.next_block()? {
                return Ok(0);
            }
        }
        let n = buf.len().min(self.block.len() - self.at);
        buf[..n].copy_from_slice(&self.block[self.at..self.at + n]);
        self.at += n;
        Ok(n)
    }
}

/// Reads until `buf` is full or the input ends; returns how much was read.
pub fn read_full<R: Read>(input: &mut R, buf: &mut [u8]) -> io::Result<usize> {
    let mut filled = 0;
    while filled < buf.len() {
        match input.read(&mut buf[filled..]) {
            Ok(0) => break,
            Ok(n) => filled += n,
            Err(error) if error.kind() == io::ErrorKind::Interrupted => {}
            Err(error) => return Err(error),
        }
    }
    Ok(filled)
}

/// Compresses `data` into the block format (blocks of at most 32 KiB of input).
pub fn compress(data: &[u8]) -> Vec<u8> {
    let mut out = Vec::with_capacity(data.len() / 2 + 16);
    for chunk in data.chunks(32 * 1024) {
        let block = lz4_flex::block::compress(chunk);
        // A 32 KiB chunk compresses to at most 32 KiB + 32 KiB/255 + 16 < 65,536 bytes.
        let length = u16::try_from(block.len()).unwrap_or(u16::MAX);
        out.extend_from_slice(&length.to_be_bytes());
        out.extend_from_slice(&block);
    }
    out
}

/// Decompresses a whole small file (a `.ccc` sensor list) of at most `limit` bytes once
/// decompressed: a few kilobytes of blocks can expand to gigabytes, so the output is
/// capped, not only the input.
pub fn decompress_all(data: &[u8], limit: u64) -> Result<Vec<u8>, Lz4Problem> {
    let mut out = Vec::new();
    Lz4Blocks::new(data)
        .take(limit.saturating_add(1))
        .read_to_end(&mut out)
        .map_err(|error| {
            match error
                .get_ref()
                .and_then(|inner| inner.downcast_ref::<Lz4Problem>())
            {
                Some(problem) => problem.clone(),
                None => Lz4Problem {
                    block: 0,
                    truncated: false,
                    message: error.to_string(),
                },
            }
        })?;
    if out.len() as u64 > limit {
        return Err(Lz4Problem {
            block: 0,
            truncated: false,
            message: format!("it decompresses to more than {limit} bytes (not read further)"),
        });
    }
    Ok(out)
}

//! Scene files that may be gzip-compressed (`.pbrt.gz`, `.ply.gz`, as pbrt-v4 reads them),
//! recognised by their first two bytes whatever their name.

use flate2::bufread::MultiGzDecoder;
use std::fs::File;
use std::io::{self, BufRead, BufReader, Read};
use std::path::Path;

const GZIP_MAGIC: [u8; 2] = [0x1f, 0x8b];
const BUFFER: usize = 1 << 20;

/// A file's bytes, decompressed if it is gzip.
pub fn read(path: &Path) -> io::Result<Vec<u8>> {
    let bytes = std::fs::read(path)?;
    if !bytes.starts_with(&GZIP_MAGIC) {
        return Ok(bytes);
    }
    let mut out = Vec::new();
    MultiGzDecoder::new(&bytes[..])
        .read_to_end(&mut out)
        .map_err(gzip_error)?;
    Ok(out)
}

fn gzip_error(e: io::Error) -> io::Error {
    io::Error::new(e.kind(), format!("gzip-compressed, but {e}"))
}

/// The most a deflate stream expands: 1032 bytes out for every byte in.
const MOST_EXPANSION: u64 = 1032;

/// A buffered reader of a file that decompresses it if it is gzip.
pub struct Source {
    inner: Inner,
    most_bytes: u64,
}

enum Inner {
    Plain(BufReader<File>),
    Gzip(BufReader<MultiGzDecoder<BufReader<File>>>),
}

impl Source {
    /// Opens `path`, looking at its first bytes.
    pub fn open(path: &Path) -> io::Result<Source> {
        let file = File::open(path)?;
        let len = file.metadata()?.len();
        let mut file = BufReader::with_capacity(BUFFER, file);
        Ok(if file.fill_buf()?.starts_with(&GZIP_MAGIC) {
            Source {
                inner: Inner::Gzip(BufReader::with_capacity(BUFFER, MultiGzDecoder::new(file))),
                most_bytes: len.saturating_mul(MOST_EXPANSION),
            }
        } else {
            Source {
                inner: Inner::Plain(file),
                most_bytes: len,
            }
        })
    }

    /// The most bytes the file can give (decompressed): a bound for what a header claims.
    pub fn most_bytes(&self) -> u64 {
        self.most_bytes
    }
}

impl Read for Source {
    fn read(&mut self, buf: &mut [u8]) -> io::Result<usize> {
        match &mut self.inner {
            Inner::Plain(r) => r.read(buf),
            Inner::Gzip(r) => r.read(buf).map_err(gzip_error),
        }
    }
}

impl BufRead for Source {
    fn fill_buf(&mut self) -> io::Result<&[u8]> {
        match &mut self.inner {
            Inner::Plain(r) => r.fill_buf(),
            Inner::Gzip(r) => r.fill_buf().map_err(gzip_error),
        }
    }

    fn consume(&mut self, amount: usize) {
        match &mut self.inner {
            Inner::Plain(r) => r.consume(amount),
            Inner::Gzip(r) => r.consume(amount),
        }
    }
}

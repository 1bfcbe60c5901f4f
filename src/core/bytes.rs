//! Little-endian binary writing and reading for checkpoints and methods' saved states: a reader
//! that never panics on short or hostile input (every read is checked).

/// Appends little-endian values to a byte vector.
#[derive(Default)]
pub struct ByteWriter(pub Vec<u8>);

impl ByteWriter {
    /// Appends a u32.
    pub fn u32(&mut self, v: u32) {
        self.0.extend_from_slice(&v.to_le_bytes());
    }
    /// Appends a u64.
    pub fn u64(&mut self, v: u64) {
        self.0.extend_from_slice(&v.to_le_bytes());
    }
    /// Appends an f32 (its bits).
    pub fn f32(&mut self, v: f32) {
        self.u32(v.to_bits());
    }
    /// Appends an f64 (its bits).
    pub fn f64(&mut self, v: f64) {
        self.u64(v.to_bits());
    }
    /// Appends raw bytes.
    pub fn bytes(&mut self, b: &[u8]) {
        self.0.extend_from_slice(b);
    }
}

/// Reads little-endian values from a byte slice; every read fails with "truncated" past the end.
pub struct ByteReader<'a> {
    b: &'a [u8],
    at: usize,
}

impl<'a> ByteReader<'a> {
    /// A reader at the start of `b`.
    pub fn new(b: &'a [u8]) -> Self {
        Self { b, at: 0 }
    }
    /// The next `n` bytes.
    pub fn take(&mut self, n: usize) -> Result<&'a [u8], String> {
        let s = self.b.get(self.at..self.at.saturating_add(n)).ok_or("truncated")?;
        self.at += n;
        Ok(s)
    }
    /// The next u32.
    pub fn u32(&mut self) -> Result<u32, String> {
        Ok(u32::from_le_bytes(self.take(4)?.try_into().unwrap_or_default()))
    }
    /// The next u64.
    pub fn u64(&mut self) -> Result<u64, String> {
        Ok(u64::from_le_bytes(self.take(8)?.try_into().unwrap_or_default()))
    }
    /// The next f32.
    pub fn f32(&mut self) -> Result<f32, String> {
        self.u32().map(f32::from_bits)
    }
    /// The next f64.
    pub fn f64(&mut self) -> Result<f64, String> {
        self.u64().map(f64::from_bits)
    }
    /// Bytes not read yet.
    pub fn remaining(&self) -> usize {
        self.b.len() - self.at
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn values_round_trip_and_short_input_is_an_error() {
        let mut w = ByteWriter::default();
        w.u32(7);
        w.f64(-1.5);
        w.f32(2.25);
        let mut r = ByteReader::new(&w.0);
        assert_eq!((r.u32().unwrap(), r.f64().unwrap(), r.f32().unwrap()), (7, -1.5, 2.25));
        assert_eq!(r.remaining(), 0);
        assert!(r.u32().is_err());
    }
}

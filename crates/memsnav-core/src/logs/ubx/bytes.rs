//! Little-endian fields of a UBX payload (interface description §3.3: all
//! multi-byte values are little-endian, floats IEEE 754). Callers check a
//! payload's length before reading its fields.

/// A payload read by byte offset.
#[derive(Clone, Copy)]
pub(super) struct Le<'a>(pub &'a [u8]);

impl Le<'_> {
    fn array<const N: usize>(&self, at: usize) -> [u8; N] {
        self.0[at..at + N].try_into().expect("slice of length N")
    }
    pub fn u8(&self, at: usize) -> u8 {
        self.0[at]
    }
    pub fn i8(&self, at: usize) -> i8 {
        i8::from_le_bytes(self.array(at))
    }
    pub fn u16(&self, at: usize) -> u16 {
        u16::from_le_bytes(self.array(at))
    }
    pub fn u32(&self, at: usize) -> u32 {
        u32::from_le_bytes(self.array(at))
    }
    pub fn i32(&self, at: usize) -> i32 {
        i32::from_le_bytes(self.array(at))
    }
    pub fn f32(&self, at: usize) -> f32 {
        f32::from_le_bytes(self.array(at))
    }
    pub fn f64(&self, at: usize) -> f64 {
        f64::from_le_bytes(self.array(at))
    }
}

//! A bit-packed message codec in the spirit of DCCL (issue #16): declare a message once as a
//! Rust type whose fields carry their bounds and resolution, and get an encoding whose size is
//! known at compile time ([`Compact::SIZE_BITS`], [`Compact::SIZE_BYTES`]).
//!
//! `#[derive(Compact)]` (from `compact-derive`) reads one attribute per field:
//!
//! | field type | attribute | bits | decoded value |
//! |---|---|---|---|
//! | `f32`, `f64` | `#[compact(min = A, max = B, resolution = R)]` | `bits_for(round((B - A) / R))` | `A + k * R`, within `R / 2` of the sent value |
//! | integers | `#[compact(min = A, max = B)]` (optional: the type's own bounds) | `bits_for(B - A)` | exact |
//! | `bool` | none | 1 | exact |
//! | `Option<number or bool>` | as the inner type | one more *value*, not one more bit: code 0 is "absent" (DCCL's default optional codec) | exact presence |
//! | a type that derives `Compact` (struct or fieldless enum) | none | its `SIZE_BITS` | as that type |
//! | `Option<such a type>` | none | 1 presence bit + its `SIZE_BITS` (zeros when absent) | as that type |
//!
//! where `bits_for(n)` is the number of bits that hold `0..=n` (`ceil(log2(n + 1))`). A
//! fieldless enum takes `bits_for(variants - 1)` bits, its variants numbered in declaration order.
//!
//! Out-of-range values on encoding follow the field's declared policy: `clamp` (the default:
//! the nearest bound is sent) or `reject` (encoding fails with [`EncodeError::OutOfRange`]).
//! A value is never wrapped. NaN is always refused ([`EncodeError::NotANumber`]).
//!
//! Decoding is strict, so a payload that is not this message is refused rather than read as
//! garbage: the length must be exactly `SIZE_BYTES`, every code must be within its field's
//! range (an enum index past the last variant, a number code past `max`), absent optional
//! sub-messages must be all zeros and the padding bits of the last byte must be zero. No input
//! makes the decoder panic.
//!
//! ```
//! use compact::Compact;
//!
//! #[derive(Compact, Debug, Clone, Copy, PartialEq)]
//! enum Mode { Park, Survey, Surface }
//!
//! #[derive(Compact, Debug, Clone, PartialEq)]
//! struct Fix {
//!     #[compact(min = -5000.0, max = 5000.0, resolution = 0.1)]
//!     x_m: f64,
//!     #[compact(min = 0.0, max = 200.0, resolution = 0.1, reject)]
//!     depth_m: f64,
//!     #[compact(min = 0, max = 15)]
//!     vehicle: u8,
//!     mode: Mode,
//!     ok: bool,
//! }
//!
//! // 17 + 11 + 4 + 2 + 1 bits.
//! assert_eq!((Fix::SIZE_BITS, Fix::SIZE_BYTES), (35, 5));
//! let f = Fix { x_m: -1234.56, depth_m: 12.34, vehicle: 3, mode: Mode::Survey, ok: true };
//! let bytes = f.to_vec().unwrap();
//! let back = Fix::decode(&bytes).unwrap();
//! assert!((back.x_m - f.x_m).abs() <= 0.05 + 1e-9);
//! assert_eq!((back.vehicle, back.mode, back.ok), (3, Mode::Survey, true));
//!
//! // x is clamped, depth is rejected, as declared.
//! let far = Fix { x_m: 9e9, ..f.clone() };
//! assert_eq!(Fix::decode(&far.to_vec().unwrap()).unwrap().x_m, 5000.0);
//! let deep = Fix { depth_m: 250.0, ..f };
//! assert!(matches!(deep.to_vec(), Err(compact::EncodeError::OutOfRange { field: "depth_m", .. })));
//! ```
//!
//! # Declaration errors
//!
//! Bad bounds are compile errors, not runtime surprises. This declaration compiles:
//!
//! ```
//! #[derive(compact::Compact)]
//! struct S { #[compact(min = 0.0, max = 10.0, resolution = 0.5)] x: f64, y: u8 }
//! assert_eq!(<S as compact::Compact>::SIZE_BITS, 5 + 8);
//! ```
//!
//! and each of these does not. A float needs all three bounds:
//!
//! ```compile_fail
//! #[derive(compact::Compact)]
//! struct S { #[compact(min = 0.0, max = 10.0)] x: f64 }
//! ```
//!
//! `max - min` must be a whole number of resolutions (here 10 / 0.3 is not):
//!
//! ```compile_fail
//! #[derive(compact::Compact)]
//! struct S { #[compact(min = 0.0, max = 10.0, resolution = 0.3)] x: f64 }
//! ```
//!
//! Integer bounds must lie within the type (a `u8` cannot reach 300):
//!
//! ```compile_fail
//! #[derive(compact::Compact)]
//! struct S { #[compact(min = 0, max = 300)] x: u8 }
//! ```
//!
//! A nested type carries its own bounds, and enums must be fieldless:
//!
//! ```compile_fail
//! #[derive(compact::Compact)]
//! enum E { A(u8), B }
//! ```
//!
//! ```compile_fail
//! #[derive(compact::Compact)]
//! struct Inner { ok: bool }
//! #[derive(compact::Compact)]
//! struct S { #[compact(min = 0, max = 1)] inner: Inner }
//! ```
//!
//! A field type that is neither a number, a bool nor a `Compact` type does not compile:
//!
//! ```compile_fail
//! #[derive(compact::Compact)]
//! struct S { name: String }
//! ```

#![warn(missing_docs)]

extern crate self as compact;

pub use compact_derive::Compact;

/// How a field treats a value outside its bounds when encoding.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum OutOfRange {
    /// Send the nearest bound.
    Clamp,
    /// Refuse to encode ([`EncodeError::OutOfRange`]).
    Reject,
}

/// Why a value could not be encoded.
#[derive(Debug, Clone, Copy, PartialEq, thiserror::Error)]
pub enum EncodeError {
    /// A `reject` field's value is outside its bounds.
    #[error("{field} = {value} is outside [{min}, {max}]")]
    OutOfRange {
        /// The field's name.
        field: &'static str,
        /// The value given (an integer shown as a float).
        value: f64,
        /// The lower bound.
        min: f64,
        /// The upper bound.
        max: f64,
    },
    /// A float field was NaN.
    #[error("{field} is not a number")]
    NotANumber {
        /// The field's name.
        field: &'static str,
    },
    /// The output buffer is shorter than the message.
    #[error("the buffer holds {have} bytes, the message needs {need}")]
    BufferTooSmall {
        /// Bytes needed.
        need: usize,
        /// Bytes given.
        have: usize,
    },
}

/// Why bytes could not be decoded as a message.
#[derive(Debug, Clone, Copy, PartialEq, Eq, thiserror::Error)]
pub enum DecodeError {
    /// The payload is not exactly the message's size.
    #[error("{got} bytes where the message has {expected}")]
    WrongLength {
        /// The message's size in bytes.
        expected: usize,
        /// The payload's size.
        got: usize,
    },
    /// The bits ran out inside a field.
    #[error("the payload ends inside a field")]
    Truncated,
    /// A field's code is outside its range (a number past its bounds, an enum index past the
    /// last variant, data in an absent sub-message).
    #[error("field {field} has an invalid code")]
    BadValue {
        /// The field's name (or the enum's type name).
        field: &'static str,
    },
    /// The padding bits after the last field are not zero.
    #[error("non-zero padding")]
    NonZeroPadding,
}

/// The number of bits that hold every integer in `0..=steps` (0 for `steps == 0`).
pub const fn bits_for(steps: u64) -> u32 {
    64 - steps.leading_zeros()
}

/// Whole bytes for `bits` bits.
pub const fn bytes_for(bits: usize) -> usize {
    bits.div_ceil(8)
}

/// A type with a bit-packed encoding of a fixed size. Derive it (`#[derive(Compact)]`).
pub trait Compact: Sized {
    /// The encoding's size in bits.
    const SIZE_BITS: usize;
    /// The encoding's size in whole bytes (the last one zero-padded).
    const SIZE_BYTES: usize = bytes_for(Self::SIZE_BITS);

    /// Writes this value's `SIZE_BITS` bits.
    fn write_bits(&self, w: &mut BitWriter<'_>) -> Result<(), EncodeError>;

    /// Reads `SIZE_BITS` bits back into a value.
    fn read_bits(r: &mut BitReader<'_>) -> Result<Self, DecodeError>;

    /// Encodes into the start of `out`, returning `SIZE_BYTES`.
    fn encode_into(&self, out: &mut [u8]) -> Result<usize, EncodeError> {
        let n = Self::SIZE_BYTES;
        let have = out.len();
        let Some(buf) = out.get_mut(..n) else {
            return Err(EncodeError::BufferTooSmall { need: n, have });
        };
        buf.fill(0);
        let mut w = BitWriter::new(buf);
        self.write_bits(&mut w)?;
        Ok(n)
    }

    /// Encodes into a new vector of `SIZE_BYTES` bytes.
    fn to_vec(&self) -> Result<Vec<u8>, EncodeError> {
        let mut v = vec![0; Self::SIZE_BYTES];
        self.encode_into(&mut v)?;
        Ok(v)
    }

    /// Decodes exactly `SIZE_BYTES` bytes (zero padding).
    fn decode(bytes: &[u8]) -> Result<Self, DecodeError> {
        if bytes.len() != Self::SIZE_BYTES {
            return Err(DecodeError::WrongLength {
                expected: Self::SIZE_BYTES,
                got: bytes.len(),
            });
        }
        let mut r = BitReader::new(bytes);
        let v = Self::read_bits(&mut r)?;
        r.finish()?;
        Ok(v)
    }
}

/// Writes bits most significant first into a zeroed byte buffer.
#[derive(Debug)]
pub struct BitWriter<'a> {
    buf: &'a mut [u8],
    pos: usize,
}

impl<'a> BitWriter<'a> {
    /// A writer at the start of `buf`, which must be zeroed.
    pub fn new(buf: &'a mut [u8]) -> Self {
        Self { buf, pos: 0 }
    }

    /// Bits written so far.
    pub fn position(&self) -> usize {
        self.pos
    }

    /// Writes the low `bits` bits of `value`, most significant first (bits past 64 are zeros).
    pub fn write(&mut self, value: u64, bits: u32) -> Result<(), EncodeError> {
        let need = bytes_for(self.pos + bits as usize);
        if need > self.buf.len() {
            return Err(EncodeError::BufferTooSmall {
                need,
                have: self.buf.len(),
            });
        }
        let mut left = bits;
        while left > 0 {
            let free = 8 - (self.pos % 8) as u32;
            let n = free.min(left);
            let chunk = (value.checked_shr(left - n).unwrap_or(0) & ((1u64 << n) - 1)) as u8;
            self.buf[self.pos / 8] |= chunk << (free - n);
            self.pos += n as usize;
            left -= n;
        }
        Ok(())
    }

    /// Writes `bits` zero bits (the body of an absent optional sub-message).
    pub fn write_zeros(&mut self, bits: usize) -> Result<(), EncodeError> {
        let mut left = bits;
        while left > 0 {
            let n = left.min(64);
            self.write(0, n as u32)?;
            left -= n;
        }
        Ok(())
    }
}

/// Reads bits most significant first.
#[derive(Debug, Clone)]
pub struct BitReader<'a> {
    buf: &'a [u8],
    pos: usize,
}

impl<'a> BitReader<'a> {
    /// A reader at the start of `buf`.
    pub fn new(buf: &'a [u8]) -> Self {
        Self { buf, pos: 0 }
    }

    /// Bits read so far.
    pub fn position(&self) -> usize {
        self.pos
    }

    /// Reads `bits` bits (at most 64).
    pub fn read(&mut self, bits: u32) -> Result<u64, DecodeError> {
        if self.pos + bits as usize > self.buf.len() * 8 {
            return Err(DecodeError::Truncated);
        }
        let mut v = 0u64;
        let mut left = bits;
        while left > 0 {
            let used = (self.pos % 8) as u32;
            let n = (8 - used).min(left);
            let byte = u64::from(self.buf[self.pos / 8]);
            let chunk = (byte >> (8 - used - n)) & ((1u64 << n) - 1);
            v = (v << n) | chunk;
            self.pos += n as usize;
            left -= n;
        }
        Ok(v)
    }

    /// Reads `bits` bits that must all be zero (an absent optional sub-message), else
    /// [`DecodeError::BadValue`] naming `field`.
    pub fn expect_zeros(&mut self, bits: usize, field: &'static str) -> Result<(), DecodeError> {
        let mut left = bits;
        while left > 0 {
            let n = left.min(64);
            if self.read(n as u32)? != 0 {
                return Err(DecodeError::BadValue { field });
            }
            left -= n;
        }
        Ok(())
    }

    /// Checks that the rest of the buffer is zero padding inside the last byte.
    pub fn finish(&self) -> Result<(), DecodeError> {
        let rest = self.buf.len() * 8 - self.pos;
        if rest >= 8 {
            return Err(DecodeError::WrongLength {
                expected: bytes_for(self.pos),
                got: self.buf.len(),
            });
        }
        if rest > 0 && self.buf[self.pos / 8] & ((1u8 << rest) - 1) != 0 {
            return Err(DecodeError::NonZeroPadding);
        }
        Ok(())
    }
}

/// A bounded float field: `min + k * resolution` for `k` in `0..=steps`.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Fixed {
    /// The field's name, for errors.
    pub name: &'static str,
    /// The lowest value (code 0).
    pub min: f64,
    /// The highest value.
    pub max: f64,
    /// The step between codes.
    pub resolution: f64,
    /// `round((max - min) / resolution)`, the highest code.
    pub steps: u64,
    /// What an out-of-range value does.
    pub policy: OutOfRange,
}

impl Fixed {
    /// The code of `v`: rounded to the nearest step, out-of-range values clamped or refused.
    pub fn code(&self, v: f64) -> Result<u64, EncodeError> {
        if v.is_nan() {
            return Err(EncodeError::NotANumber { field: self.name });
        }
        let k = ((v - self.min) / self.resolution).round();
        if k < 0.0 || k > self.steps as f64 {
            return match self.policy {
                OutOfRange::Clamp if k < 0.0 => Ok(0),
                OutOfRange::Clamp => Ok(self.steps),
                OutOfRange::Reject => Err(EncodeError::OutOfRange {
                    field: self.name,
                    value: v,
                    min: self.min,
                    max: self.max,
                }),
            };
        }
        Ok(k as u64)
    }

    /// The value of code `k`, refused past `steps`.
    pub fn value(&self, k: u64) -> Result<f64, DecodeError> {
        if k > self.steps {
            return Err(DecodeError::BadValue { field: self.name });
        }
        if k == self.steps {
            return Ok(self.max);
        }
        Ok(self.min + k as f64 * self.resolution)
    }
}

/// A bounded integer field: `min + k` for `k` in `0..=max - min`.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct Int {
    /// The field's name, for errors.
    pub name: &'static str,
    /// The lowest value (code 0).
    pub min: i128,
    /// The highest value.
    pub max: i128,
    /// What an out-of-range value does.
    pub policy: OutOfRange,
}

impl Int {
    /// The code of `v`, out-of-range values clamped or refused.
    pub fn code(&self, v: i128) -> Result<u64, EncodeError> {
        let v = if v < self.min || v > self.max {
            match self.policy {
                OutOfRange::Clamp => v.clamp(self.min, self.max),
                OutOfRange::Reject => {
                    return Err(EncodeError::OutOfRange {
                        field: self.name,
                        value: v as f64,
                        min: self.min as f64,
                        max: self.max as f64,
                    });
                }
            }
        } else {
            v
        };
        Ok((v - self.min) as u64)
    }

    /// The value of code `k`, refused past `max`.
    pub fn value(&self, k: u64) -> Result<i128, DecodeError> {
        let v = self.min + i128::from(k);
        if v > self.max {
            return Err(DecodeError::BadValue { field: self.name });
        }
        Ok(v)
    }
}

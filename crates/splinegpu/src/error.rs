//! Errors: what was wrong with the input (and where), and what went wrong on the GPU.

use std::fmt;

/// Where an [`InputError`] lies.
#[derive(Clone, Debug, PartialEq, Eq)]
#[non_exhaustive]
pub enum Location {
    /// An argument of a library call (a [`Curve`](crate::Curve)'s points, a
    /// [`Sampling`](crate::Sampling)), not yet placed in a document or a batch.
    Argument,
    /// The input document itself (a top-level key, or the JSON syntax).
    Document,
    /// The curve with this 0-based index (in a document's `"curves"`, or in a batch).
    Curve(usize),
    /// The surface with this 0-based index (in a document's `"surfaces"`).
    Surface(usize),
}

/// Bad input: names the place (document or curve index), the field and the offending value.
///
/// Displayed as the CLI prints it, e.g.
/// `curve 5: "t" must be strictly increasing: t[3] = 2 follows t[2] = 2` or
/// `document: "curves" must not be empty`.
#[derive(Clone, Debug, PartialEq, Eq)]
#[non_exhaustive]
pub struct InputError {
    /// The document or the curve the error belongs to.
    pub location: Location,
    /// The JSON key at fault, when there is one.
    pub field: Option<String>,
    /// What is wrong, with the value.
    pub message: String,
}

impl InputError {
    /// An error in `field` of a library call's argument; [`InputError::in_curve`] places it in
    /// a curve, [`InputError::in_document`] at the document's level.
    #[must_use]
    pub fn field(field: impl Into<String>, message: impl Into<String>) -> Self {
        Self {
            location: Location::Argument,
            field: Some(field.into()),
            message: message.into(),
        }
    }

    /// A document-level error with no single key to blame (a JSON syntax error, say).
    #[must_use]
    pub fn document(message: impl Into<String>) -> Self {
        Self {
            location: Location::Document,
            field: None,
            message: message.into(),
        }
    }

    /// The same error, placed at the document's level (a top-level key).
    #[must_use]
    pub fn in_document(mut self) -> Self {
        self.location = Location::Document;
        self
    }

    /// The same error, placed in the curve with index `index`.
    #[must_use]
    pub fn in_curve(mut self, index: usize) -> Self {
        self.location = Location::Curve(index);
        self
    }

    /// The same error, placed in the surface with index `index`.
    #[must_use]
    pub fn in_surface(mut self, index: usize) -> Self {
        self.location = Location::Surface(index);
        self
    }
}

impl fmt::Display for InputError {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self.location {
            Location::Argument => {}
            Location::Document => write!(f, "document: ")?,
            Location::Curve(i) => write!(f, "curve {i}: ")?,
            Location::Surface(i) => write!(f, "surface {i}: ")?,
        }
        match &self.field {
            Some(field) => write!(f, "\"{field}\" {}", self.message),
            None => write!(f, "{}", self.message),
        }
    }
}

impl std::error::Error for InputError {}

/// A number as an error message shows it: as JSON would write it where that is short (`2`,
/// `0.5`, `-3.25`), in exponent form where plain digits would run on (`1e-300`, `1.5e200`, not
/// 300 zeros). Both forms are the shortest that read back as the same f64.
#[derive(Clone, Copy, Debug)]
pub(crate) struct Shown(pub f64);

impl fmt::Display for Shown {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        let size = self.0.abs();
        if size == 0.0 || !size.is_finite() || (1e-6..1e16).contains(&size) {
            write!(f, "{}", self.0)
        } else {
            write!(f, "{:e}", self.0)
        }
    }
}

/// A failure of the GPU path that is not the input's fault.
#[derive(Debug, thiserror::Error)]
#[non_exhaustive]
pub enum GpuError {
    /// wgpu found no adapter (no Vulkan, Metal or DX12 driver).
    #[error("no GPU adapter found: {0}")]
    NoAdapter(String),
    /// The adapter refused to create a device.
    #[error("could not create a device on {adapter}: {source}")]
    RequestDevice {
        /// The adapter's name.
        adapter: String,
        /// wgpu's reason.
        source: wgpu::RequestDeviceError,
    },
    /// A value does not fit the GPU's float32 range.
    #[error(
        "curve {curve}: {what} exceeds the float32 range of the GPU backend (use the cpu backend)"
    )]
    OutOfRange {
        /// The curve's index.
        curve: usize,
        /// What overflowed.
        what: &'static str,
    },
    /// One of the job's input tables is larger than a storage binding may be on this device.
    #[error(
        "the job's {table} table needs {bytes} bytes, more than this device binds at once ({limit})"
    )]
    TooLarge {
        /// Which table.
        table: &'static str,
        /// Its size.
        bytes: u64,
        /// The device's max_storage_buffer_binding_size.
        limit: u64,
    },
    /// A caller's target buffer cannot take the samples
    /// ([`GpuContext::record_into`](crate::GpuContext::record_into)).
    #[error(transparent)]
    Target(#[from] TargetError),
    /// wgpu reported an error (validation, out of memory, lost device) or a mapping failed:
    /// wgpu's own error, kept as the source.
    #[error("GPU failure: {0}")]
    Device(#[source] Box<dyn std::error::Error + Send + Sync + 'static>),
}

impl GpuError {
    /// A [`GpuError::Device`] from wgpu's error (or a message of our own).
    pub(crate) fn device(
        error: impl Into<Box<dyn std::error::Error + Send + Sync + 'static>>,
    ) -> Self {
        Self::Device(error.into())
    }
}

/// Why a caller's buffer cannot be the target of
/// [`GpuContext::record_into`](crate::GpuContext::record_into): the caller's mistake, not the
/// device's.
#[derive(Clone, Debug, PartialEq, Eq, thiserror::Error)]
#[non_exhaustive]
pub enum TargetError {
    /// The buffer was made without `BufferUsages::STORAGE`.
    #[error("the target buffer needs STORAGE usage")]
    MissingStorageUsage,
    /// The offset is not a multiple of the device's `min_storage_buffer_offset_alignment`.
    #[error("the target offset {offset} is not a multiple of {alignment}")]
    MisalignedOffset {
        /// The caller's offset, in bytes.
        offset: u64,
        /// The device's alignment, in bytes.
        alignment: u64,
    },
    /// The buffer holds fewer bytes from the offset on than the job writes.
    #[error("the target buffer holds {available} bytes from its offset; the job needs {needed}")]
    TooSmall {
        /// Bytes from the offset to the buffer's end.
        available: u64,
        /// Bytes the job writes ([`OutputLayout::bytes`](crate::OutputLayout::bytes)).
        needed: u64,
    },
}

#[cfg(test)]
mod tests {
    use super::Shown;

    #[test]
    fn numbers_are_shown_short_and_read_back_the_same() {
        for (v, want) in [
            (2.0, "2"),
            (0.5, "0.5"),
            (-3.25, "-3.25"),
            (0.0, "0"),
            (1e-6, "0.000001"),
            (123_456_789_012_345.0, "123456789012345"),
            (0.1 + 0.2, "0.30000000000000004"),
            (1e-7, "1e-7"),
            (1e16, "1e16"),
            (-1e-300, "-1e-300"),
            (1.5e200, "1.5e200"),
            (f64::MAX, "1.7976931348623157e308"),
            (5e-324, "5e-324"),
            (f64::INFINITY, "inf"),
        ] {
            let shown = Shown(v).to_string();
            assert_eq!(shown, want);
            if v.is_finite() {
                assert_eq!(shown.parse::<f64>(), Ok(v));
            }
        }
    }
}

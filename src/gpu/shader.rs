//! The WGSL source and the constants the Rust side shares with it.

/// `shaders/eval.wgsl`: evaluates runs of samples from power-form coefficients.
pub const EVAL_WGSL: &str = include_str!("../../shaders/eval.wgsl");

/// The kernel's workgroup size; `const WG_SIZE` in `shaders/eval.wgsl` (checked by a test).
pub const WG_SIZE: u32 = 64;

/// The kernel's entry point.
pub const ENTRY_POINT: &str = "main";

/// The pipeline-overridable constant naming how many invocations share a run.
pub const LANES_CONSTANT: &str = "LANES";

/// The pipeline-overridable constant naming the one run mode a pipeline evaluates.
pub const MODE_CONSTANT: &str = "MODE";

//! # umbra-conformance — the hard-case conformance suite
//!
//! Numerically nasty scenes (`tests/hard-cases/*.toml`: the eye inside a volume, the near
//! plane slicing one, lights at infinity or touching an occluder, 300 overlapping volumes,
//! open and non-manifold meshes, grazing light, coordinates at 1e6, NaN…), each rendered by
//! every technique on the device you give it and judged against the exact CPU reference
//! (`umbra-reference`): per technique a tolerance with its reason ([`judge`]), per case the
//! documented exceptions ([`cases`]), plus zero validation messages (the caller's context
//! counts them), no NaN in any read-back and identical output on two runs ([`run`]).
//!
//! ```no_run
//! use umbra_conformance::{run_case, CASES};
//! let ctx = umbra_vk::Context::new().unwrap();
//! let dir = std::path::Path::new("tests/hard-cases");
//! for case in CASES {
//!     let run = run_case(&ctx, dir, case, (256, 192)).unwrap();
//!     println!("{}: {}", run.title, if run.ok() { "conformant" } else { "FAILED" });
//! }
//! ```
//!
//! `tests/hard_cases.rs` runs it on the suite's device; `umbra-bench hard-cases` runs it on
//! several and writes `docs/hard-cases.md`.

#![warn(missing_docs)]

pub mod cases;
mod error;
pub mod judge;
pub mod report;
pub mod run;

pub use cases::{case, Case, Expect, Outcome, CASES, TECHNIQUES};
pub use error::{ConformanceError, ConformanceResult};
pub use judge::{Judgement, TEXEL_BAND};
pub use run::{case_path, run_case, CaseRun, TechniqueRun, Verdict};

//! The names most uses of the ball law need, for one glob import. The
//! rigid-body types (`RigidBody`, `Contact`, …) are left out: their names
//! would clash with a physics engine's prelude in a second glob import;
//! import them by name.
//!
//! ```
//! use kimpact::prelude::*;
//! use kimpact::nalgebra::Vector2;
//!
//! let law = Law::new(LawParams { dissipation: 0.01_f64, ..Default::default() })?;
//! let a = Body::new(1.0, Vector2::new(1.0, 0.0))?;
//! let b = Body::new(1.0, Vector2::zeros())?;
//! let impact: Impact<f64, 2> = law.resolve(&a, &b, &Vector2::x())?.expect("approaching");
//! assert!(impact.restitution < 1.0);
//! # Ok::<(), LawError>(())
//! ```

pub use crate::{Body, Energies, FixedPartner, Impact, Law, LawError, LawParams};

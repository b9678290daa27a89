//! The plugin in headless bevy_rapier apps, written once for 2D and 3D
//! (compiled by bevy_kimpact2d and bevy_kimpact3d).
//!
//! `harness.rs` builds the test app; `law.rs` checks the law through the
//! plugin, `rigid.rs` on marked boxes and capsules, `app.rs` what the
//! plugin promises the app it is added to.

#[cfg(feature = "dim2")]
use bevy_kimpact2d as bk;
#[cfg(feature = "dim3")]
use bevy_kimpact3d as bk;

#[path = "plugin/app.rs"]
mod app;
#[path = "plugin/harness.rs"]
mod harness;
#[path = "plugin/law.rs"]
mod law;
#[path = "plugin/rigid.rs"]
mod rigid;

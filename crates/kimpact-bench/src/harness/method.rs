//! Who simulates: the exact reference or rapier in one of kimpact's modes.

use kimpact::Mode;

/// Who simulates: the reference, or rapier in one of the adapter's modes
/// (`kimpact::Mode`, the one type every kimpact crate shares). Ordered
/// reference first, then the modes cheapest first.
#[derive(Copy, Clone, Debug, PartialEq, Eq, PartialOrd, Ord, Hash)]
pub enum Method {
    /// The exact event-driven reference (`kimpact-reference`).
    Reference,
    /// rapier, with kimpact in this mode (`Native`: rapier unchanged).
    Rapier(Mode),
}

impl Method {
    /// rapier in every mode, cheapest first.
    pub const RAPIER: [Method; 4] = [
        Method::Rapier(Mode::Native),
        Method::Rapier(Mode::Restitution),
        Method::Rapier(Mode::Impulse),
        Method::Rapier(Mode::Exact),
    ];
    /// Native rapier.
    pub const NATIVE: Method = Method::Rapier(Mode::Native);

    /// `reference`, or the mode's name.
    pub fn name(self) -> &'static str {
        match self {
            Method::Reference => "reference",
            Method::Rapier(m) => m.name(),
        }
    }

    /// The mode, for rapier.
    pub fn mode(self) -> Option<Mode> {
        match self {
            Method::Reference => None,
            Method::Rapier(m) => Some(m),
        }
    }
}

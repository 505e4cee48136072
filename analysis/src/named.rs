//! Choices with a fixed set of names (sigmoid, lapse mode, test, unit, preset): the names a
//! command line offers and a report prints. The library's own trait, so that its types need
//! no command-line crate; the `blurlab` binary turns it into a value parser.

/// A value chosen from `ALL` by its `name`.
pub trait Named: Copy + Sized + 'static {
    const ALL: &'static [Self];
    fn name(self) -> &'static str;

    /// The value called `name`, if any.
    fn by_name(name: &str) -> Option<Self> {
        Self::ALL.iter().copied().find(|v| v.name() == name)
    }
}

//! The command line's names of the libraries' named enums (`renderer::named!`): one value
//! parser, so `--help` lists the names and a wrong one is refused with them.

use clap::builder::{PossibleValuesParser, TypedValueParser};
use renderer::named::Named;

/// A clap value parser offering `T`'s names.
pub fn named<T: Named + Clone + Send + Sync>() -> impl TypedValueParser<Value = T> {
    PossibleValuesParser::new(T::ALL.iter().map(|v| v.name()))
        .map(|s| T::by_name(&s).expect("clap offers only the names"))
}

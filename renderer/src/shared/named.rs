//! The one way the suite names the values of an enum: [`Named`] (every value, its name, the
//! value of a name with an error that lists the known ones) and the [`named!`](crate::named!)
//! macro that writes it, with `ALL`, `name` and `by_name` as inherent items (callers need no
//! import), `Display` and `FromStr`, from one table of names. Serde stays the type's own
//! choice: the conditions' names read and write through the names (`condition`), other enums
//! derive it with the same spellings. Depends on std and anyhow only (the light core).

/// A value chosen from `ALL` by its `name`.
pub trait Named: Copy + Sized + 'static {
    /// What a value is, in messages ("point set").
    const WHAT: &'static str;
    /// Every value, in the order help texts list them.
    const ALL: &'static [Self];
    /// The value's name (files, command lines, reports).
    fn name(self) -> &'static str;

    /// The value called `name`; the error lists the known names.
    fn by_name(name: &str) -> anyhow::Result<Self> {
        match Self::ALL.iter().copied().find(|v| v.name() == name) {
            Some(v) => Ok(v),
            None => anyhow::bail!(
                "unknown {} {name:?}; expected one of {}",
                Self::WHAT,
                Self::names().join(", ")
            ),
        }
    }

    /// Every name, in the order of `ALL`.
    fn names() -> Vec<&'static str> {
        Self::ALL.iter().map(|v| v.name()).collect()
    }
}

/// `named!(Type, "what", [Variant => "name", ...])`: [`Named`] for an enum, its inherent `ALL`
/// (an array), `name` and `by_name`, and `Display` and `FromStr` by name.
#[macro_export]
macro_rules! named {
    ($ty:ident, $what:literal, [$($variant:ident => $name:literal),+ $(,)?]) => {
        impl $crate::named::Named for $ty {
            const WHAT: &'static str = $what;
            const ALL: &'static [Self] = &$ty::ALL;
            fn name(self) -> &'static str {
                $ty::name(self)
            }
        }

        impl $ty {
            /// Every variant, in the order help texts list them.
            pub const ALL: [$ty; [$($name),+].len()] = [$($ty::$variant),+];

            /// The variant's name.
            pub fn name(self) -> &'static str {
                match self {
                    $($ty::$variant => $name),+
                }
            }

            /// The variant called `name`; the error lists the known names.
            pub fn by_name(name: &str) -> anyhow::Result<Self> {
                <$ty as $crate::named::Named>::by_name(name)
            }
        }

        impl std::fmt::Display for $ty {
            fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
                f.write_str(self.name())
            }
        }

        impl std::str::FromStr for $ty {
            type Err = anyhow::Error;
            fn from_str(s: &str) -> anyhow::Result<Self> {
                Self::by_name(s)
            }
        }
    };
}

//! Names for the options of the library's algorithms (estimators, line kinds,
//! criteria), so that a command line, a configuration file or a Python caller
//! spells them the same way: `NAMES`, `name()`, [`std::fmt::Display`],
//! [`std::str::FromStr`], serde's (de)serialization as that name and, with the
//! feature `clap`, clap's `ValueEnum`, from one table per enum.

/// Give a fieldless enum its names: `named!(Kinds, "line kind", { Ridges =>
/// "ridges", ... })` adds `Kinds::NAMES`, `Kinds::name`, `Display`, a `FromStr`
/// whose error lists the names, and `Serialize`/`Deserialize` as the name.
macro_rules! named {
    ($ty:ident, $what:literal, { $($variant:ident => $name:literal),+ $(,)? }) => {
        impl $ty {
            /// Every name, in the order of the variants.
            pub const NAMES: &'static [&'static str] = &[$($name),+];

            /// The name of this choice.
            pub fn name(self) -> &'static str {
                match self {
                    $($ty::$variant => $name),+
                }
            }
        }

        impl std::fmt::Display for $ty {
            fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
                f.write_str(self.name())
            }
        }

        impl std::str::FromStr for $ty {
            type Err = $crate::Error;

            fn from_str(name: &str) -> $crate::Result<$ty> {
                match name {
                    $($name => Ok($ty::$variant),)+
                    _ => Err($crate::Error::unknown_name($what, name, $ty::NAMES)),
                }
            }
        }

        #[cfg(feature = "clap")]
        impl clap::ValueEnum for $ty {
            fn value_variants<'a>() -> &'a [Self] {
                &[$($ty::$variant),+]
            }

            fn to_possible_value(&self) -> Option<clap::builder::PossibleValue> {
                Some(clap::builder::PossibleValue::new(self.name()))
            }
        }

        impl serde::Serialize for $ty {
            fn serialize<S: serde::Serializer>(&self, serializer: S) -> std::result::Result<S::Ok, S::Error> {
                serializer.serialize_str(self.name())
            }
        }

        impl<'de> serde::Deserialize<'de> for $ty {
            fn deserialize<D: serde::Deserializer<'de>>(deserializer: D) -> std::result::Result<$ty, D::Error> {
                let name = <std::borrow::Cow<'de, str>>::deserialize(deserializer)?;
                name.parse().map_err(serde::de::Error::custom)
            }
        }
    };
}

pub(crate) use named;

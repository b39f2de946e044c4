//! Named enumerations: an enum whose values JavaScript knows by name (fingers, face anchors,
//! body joints), declared as one list from which come the variants, `ALL`, `NAMES`, `COUNT`,
//! `index`, `as_str` and `from_name`.

/// Declares a named enumeration:
///
/// ```text
/// named_enum! {
///     /// What it is.
///     #[derive(Clone, Copy, Debug, PartialEq, Eq)]
///     pub enum Finger {
///         /// Thumb.
///         Thumb = "thumb",
///         /// Index finger.
///         Index = "index",
///     }
/// }
/// ```
///
/// Variants are numbered from 0 in the order given (`index`); `NAMES[index]` is the JS name.
macro_rules! named_enum {
    (
        $(#[$meta:meta])*
        pub enum $ty:ident {
            $( $(#[$vmeta:meta])* $variant:ident = $name:literal, )+
        }
    ) => {
        $(#[$meta])*
        pub enum $ty {
            $( $(#[$vmeta])* $variant, )+
        }

        impl $ty {
            /// How many there are.
            pub const COUNT: usize = [$($name),+].len();
            /// Every value, in index order.
            pub const ALL: [$ty; Self::COUNT] = [$($ty::$variant),+];
            /// Every JS name, in [`Self::ALL`] order.
            pub const NAMES: [&'static str; Self::COUNT] = [$($name),+];

            /// Position in [`Self::ALL`] (0 for the first).
            #[inline]
            #[must_use]
            pub const fn index(self) -> usize {
                self as usize
            }

            /// The JS name.
            #[must_use]
            pub const fn as_str(self) -> &'static str {
                match self {
                    $($ty::$variant => $name,)+
                }
            }

            /// The value of a JS name (`None` for any other string).
            #[must_use]
            pub fn from_name(name: &str) -> Option<$ty> {
                Self::ALL.into_iter().find(|v| v.as_str() == name)
            }
        }
    };
}

pub(crate) use named_enum;

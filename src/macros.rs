//! The crate's two enum shapes, written once: the unit-variant error enums
//! of the set-up edges, and the index (`ALL`, `from_index`) of the
//! fieldless enums numbered by their discriminants.

/// An error enum of unit variants, each `Variant => "message"`, with its
/// `Display` (the message) and `core::error::Error`.
macro_rules! unit_error {
    (
        $(#[$meta:meta])*
        pub enum $name:ident {
            $( $(#[$vmeta:meta])* $variant:ident => $msg:literal, )+
        }
    ) => {
        $(#[$meta])*
        pub enum $name {
            $( $(#[$vmeta])* $variant, )+
        }

        impl core::error::Error for $name {}

        impl core::fmt::Display for $name {
            fn fmt(&self, f: &mut core::fmt::Formatter<'_>) -> core::fmt::Result {
                f.write_str(match self {
                    $( Self::$variant => $msg, )+
                })
            }
        }
    };
}

/// `ALL` (every variant, in discriminant order) and `from_index` (the
/// variant of a discriminant) for a fieldless enum declared just before,
/// named with its variants: `indexed_enum! { Name: A, B, … }`. Checked at
/// compile time: the list names every variant (an exhaustive `match`) and
/// the discriminants are `0, 1, …` in its order.
macro_rules! indexed_enum {
    ($name:ident: $($variant:ident),+ $(,)?) => {
        impl $name {
            /// Every variant, in index order.
            pub const ALL: [Self; [$(Self::$variant),+].len()] = [$(Self::$variant),+];

            /// The variant numbered `n` (its discriminant), `None` for
            /// `n ≥ ALL.len()`.
            #[must_use]
            pub const fn from_index(n: u8) -> Option<Self> {
                if (n as usize) < Self::ALL.len() {
                    Some(Self::ALL[n as usize])
                } else {
                    None
                }
            }
        }

        const _: () = {
            let _every_variant_listed = |e: $name| match e {
                $($name::$variant)|+ => (),
            };
            let mut i = 0;
            while i < $name::ALL.len() {
                assert!($name::ALL[i] as usize == i, "discriminants are not 0, 1, …");
                i += 1;
            }
        };
    };
}

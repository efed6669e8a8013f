//! How the configuration declares its keys: each section of [`super::config`] (and each contact
//! law's parameters) is written through `scene_section!`, which keeps every field's doc comment as
//! its description and its `#[key(...)]` line as a [`KeySpec`] (unit, range, plausible SI values);
//! [`super::keys`] turns them into the key listing and the unit warnings.

/// What a field's `#[key(...)]` line declares.
#[derive(Clone, Copy, Debug)]
pub struct KeySpec {
    /// SI unit (empty when dimensionless or not a quantity).
    pub unit: &'static str,
    /// The allowed values in words (`> 0`, `[0, 1)`, …), as `validate` checks them; empty: any.
    pub range: &'static str,
    /// The allowed words of a text key (an enum), e.g. `random`, `lattice`, `file`.
    pub one_of: &'static [&'static str],
    /// The range a value in the SI unit plausibly lies in; outside it `check` warns.
    pub plausible: Option<(f64, f64)>,
    /// The keys of a sub-table (`[material]`, `[contact.linear]`, …).
    pub table: Option<&'static [KeyDoc]>,
}

impl KeySpec {
    /// Nothing declared (the base of each `#[key(...)]`).
    pub const NONE: KeySpec = KeySpec { unit: "", range: "", one_of: &[], plausible: None, table: None };
}

/// One field of a section: its name, doc comment lines and declaration.
#[derive(Clone, Copy, Debug)]
pub struct KeyDoc {
    /// The field's (TOML) name.
    pub name: &'static str,
    /// Its doc comment, a line each.
    pub doc: &'static [&'static str],
    /// Its unit, range and plausible values.
    pub spec: KeySpec,
}

/// Declares a section of the scene configuration: the struct as written, plus `KEYS`, its fields'
/// [`KeyDoc`]s. Every field carries its doc comment and a `#[key(unit: .., range: .., ..)]` line
/// with [`KeySpec`]'s fields (the rest default to none).
macro_rules! scene_section {
    (
        $(#[$meta:meta])*
        pub struct $name:ident {
            $(
                $(#[doc = $doc:literal])*
                #[key($($spec:tt)*)]
                pub $field:ident : $ty:ty,
            )*
        }
    ) => {
        $(#[$meta])*
        pub struct $name {
            $( $(#[doc = $doc])* pub $field: $ty, )*
        }

        impl $name {
            /// The section's keys (`physics::keys`).
            pub const KEYS: &'static [$crate::physics::key_spec::KeyDoc] = &[
                $($crate::physics::key_spec::KeyDoc {
                    name: stringify!($field),
                    doc: &[$($doc),*],
                    spec: $crate::physics::key_spec::KeySpec { $($spec)*, ..$crate::physics::key_spec::KeySpec::NONE },
                },)*
            ];
        }
    };
}
pub(crate) use scene_section;

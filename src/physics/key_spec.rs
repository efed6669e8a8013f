//! How the configuration declares its keys: each section of [`super::config`] (and each contact
//! law's parameters) is a plain struct deriving [`SceneKeys`], which keeps every field's doc comment
//! as its description and its `#[key(...)]` line as a [`KeySpec`] (unit, range, plausible SI
//! values); [`super::keys`] turns them into the key listing and the unit warnings.

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

/// `#[derive(SceneKeys)]` on a section: its `KEYS`, each field's [`KeyDoc`] from the field's doc
/// comment and its `#[key(unit: .., range: .., ..)]` line with [`KeySpec`]'s fields (the rest
/// default to none); the derive is the `demsweep-derive` crate (`derive/`).
pub(crate) use demsweep_derive::SceneKeys;

#[cfg(test)]
mod tests {
    use super::*;

    /// A section as the configuration declares one.
    #[derive(SceneKeys)]
    #[allow(dead_code)]
    struct Section {
        /// Its length (m),
        /// in two lines.
        #[key(unit: "m", range: "> 0", plausible: Some((1e-3, 1.0)))]
        length: f64,
        /// A word.
        #[key(one_of: &["near", "far"])]
        word: String,
        #[key()]
        bare: bool,
    }

    #[test]
    fn the_derive_keeps_each_fields_name_doc_lines_and_key_line() {
        let names: Vec<&str> = Section::KEYS.iter().map(|k| k.name).collect();
        assert_eq!(names, ["length", "word", "bare"]);
        let [length, word, bare] = Section::KEYS else { panic!("three keys") };
        assert_eq!(length.doc, [" Its length (m),", " in two lines."]);
        let spec = length.spec;
        assert_eq!((spec.unit, spec.range, spec.plausible), ("m", "> 0", Some((1e-3, 1.0))));
        assert!(spec.one_of.is_empty() && spec.table.is_none());
        assert_eq!((word.doc, word.spec.one_of, word.spec.unit), (&[" A word."][..], &["near", "far"][..], ""));
        assert!(bare.doc.is_empty() && bare.spec.range.is_empty() && bare.spec.plausible.is_none());
    }
}

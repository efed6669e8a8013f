//! The table of contact laws: `contact.law` names one, `[contact.<name>]` holds its parameters,
//! and [`ContactConfig::dispatch`] is the one place that turns the choice into a law. Every caller
//! that needs the scene's law (the simulation, time-step and stability estimates, tune's screen,
//! benchmarks) goes through it, so a law added here is used everywhere.
//!
//! Adding a law: a file implementing [`ContactLaw`](super::ContactLaw) whose parameters are its
//! serde fields (defaults for all), then one line in the `contact_laws!` table at the bottom.

use serde::{Deserialize, Serialize};

use super::{ContactLaw, HertzMindlin, HystereticLinear, LinearSpringDashpot};
use crate::physics::key_spec::{KeyDoc, KeySpec};

/// Work done with the scene's law, whichever it is (a generic closure).
pub trait LawVisitor {
    /// What the work returns.
    type Output;
    /// Does the work with `law`.
    fn visit<L: RegisteredLaw>(self, law: &L) -> Self::Output;
}

/// A law of the table: it can be found in a [`ContactConfig`].
pub trait RegisteredLaw: ContactLaw {
    /// This law, if it is the one `contact` chooses.
    fn chosen_in(contact: &ContactConfig) -> Option<&Self>;
}

macro_rules! contact_laws {
    ($($(#[doc = $doc:literal])* $variant:ident($field:ident): $law:ty,)+) => {
        /// Which contact force law (`contact.law`).
        #[derive(Clone, Copy, Debug, PartialEq, Eq, Serialize, Deserialize)]
        #[serde(rename_all = "snake_case")]
        pub enum ContactLawKind {
            $($(#[doc = $doc])* $variant,)+
        }

        /// `[contact]`: the law, the options every law shares, and each law's parameters in a table
        /// of its own (`[contact.linear]`, …), so that a sweep may switch laws.
        #[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
        #[serde(deny_unknown_fields, default)]
        pub struct ContactConfig {
            /// The force law.
            pub law: ContactLawKind,
            /// Allow a tensile (attractive) normal force from damping instead of clamping `Fn ≥ 0`.
            pub allow_tension: bool,
            $($(#[doc = $doc])* pub $field: $law,)+
        }

        impl ContactConfig {
            /// The `[contact]` keys (`physics::keys`): the law, the shared options, each law's table.
            pub const KEYS: &'static [KeyDoc] = &[
                KeyDoc { name: "law", doc: &["The force law."], spec: KeySpec { one_of: &[$(stringify!($field)),+], ..KeySpec::NONE } },
                KeyDoc {
                    name: "allow_tension",
                    doc: &["Allow a tensile (attractive) normal force from damping instead of clamping `Fn ≥ 0`."],
                    spec: KeySpec { range: "true or false", ..KeySpec::NONE },
                },
                $(KeyDoc { name: stringify!($field), doc: &[$($doc),*], spec: KeySpec { table: Some(<$law>::KEYS), ..KeySpec::NONE } },)+
            ];
        }

        impl Default for ContactConfig {
            fn default() -> Self {
                Self { law: ContactLawKind::HertzMindlin, allow_tension: false, $($field: <$law>::default(),)+ }
            }
        }

        impl ContactLawKind {
            /// Every law of the table.
            pub const ALL: &[ContactLawKind] = &[$(ContactLawKind::$variant,)+];
        }

        impl ContactConfig {
            /// Runs `visitor` with the chosen law: the one dispatch from configuration to law.
            pub fn dispatch<V: LawVisitor>(&self, visitor: V) -> V::Output {
                match self.law {
                    $(ContactLawKind::$variant => visitor.visit(&self.$field),)+
                }
            }
        }

        $(impl RegisteredLaw for $law {
            fn chosen_in(contact: &ContactConfig) -> Option<&Self> {
                (contact.law == ContactLawKind::$variant).then_some(&contact.$field)
            }
        })+
    };
}

contact_laws! {
    /// The paper's Hertz-Mindlin law with the spec's fixes (the default).
    HertzMindlin(hertz_mindlin): HertzMindlin,
    /// Linear spring-dashpot (Cundall-Strack) with Coulomb friction.
    Linear(linear): LinearSpringDashpot,
    /// Hysteretic linear spring (Walton-Braun): plastic loading, stiffer elastic unloading.
    HystereticLinear(hysteretic_linear): HystereticLinear,
}

impl ContactConfig {
    /// Problems with the chosen law's parameters, as (full key, reason).
    pub fn problems(&self) -> Vec<(String, String)> {
        struct Problems;
        impl LawVisitor for Problems {
            type Output = Vec<(String, String)>;
            fn visit<L: RegisteredLaw>(self, law: &L) -> Self::Output {
                let section = format!("contact.{}", law.name());
                law.problems().into_iter().map(|(key, reason)| (format!("{section}.{key}"), reason)).collect()
            }
        }
        self.dispatch(Problems)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn each_law_is_found_under_its_own_name() {
        struct Name;
        impl LawVisitor for Name {
            type Output = &'static str;
            fn visit<L: RegisteredLaw>(self, law: &L) -> &'static str {
                law.name()
            }
        }
        for &law in ContactLawKind::ALL {
            let contact = ContactConfig { law, ..Default::default() };
            let value = toml::Value::try_from(law).expect("a law name");
            let name = contact.dispatch(Name);
            assert_eq!(value.as_str(), Some(name));
            // Its parameter table is the field of the same name.
            let table = toml::Value::try_from(&contact).expect("serialises");
            assert!(table.get(name).is_some_and(toml::Value::is_table), "[contact.{name}]");
        }
    }
}

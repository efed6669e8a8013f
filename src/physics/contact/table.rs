//! The table of contact models: each kind's enum (the choice key's values) and `Any*` enum (the
//! run-time choice), the presets `contact.law` names, `[contact]` itself, and one row per model from
//! which `contact_models!` (`registry`) makes their implementations. Adding a model is a file
//! implementing its kind's trait ([`super::NormalModel`], …), its variant in its kind's two enums,
//! and its row (with `, table` and a `ContactConfig` field of that name when it has parameters: its
//! serde fields, defaults for all).

use serde::{Deserialize, Serialize};

use super::composed::Composed;
use super::damping::{PaperDamping, ViscoelasticDamping, ViscousDamping};
use super::law::{ContactLaw, ContactState, PairProperties};
use super::normal::{HertzNormal, HystereticNormal, LinearNormal};
use super::registry::contact_models;
use super::rolling::{ConstantTorque, NoRolling};
use super::sub_model::{DampingModel, NormalModel, Problems, RollingModel, Stiffness, TangentialModel};
use super::tangential::{LinearTangential, MindlinTangential};
use crate::physics::key_spec::{KeyDoc, KeySpec, SceneKeys};
use crate::physics::number::exact;

/// Work done with the scene's law, whichever it is (a generic closure).
pub trait LawVisitor {
    /// What the work returns.
    type Output;
    /// Does the work with `law`.
    fn visit<L: RegisteredLaw>(self, law: &L) -> Self::Output;
}

/// A law that can be found in a [`ContactConfig`].
pub trait RegisteredLaw: ContactLaw {
    /// This law with the parameters of `contact`, if `contact` chooses it.
    fn chosen_in(contact: &ContactConfig) -> Option<Self>;
}

/// A sub-model of the table: built from a [`ContactConfig`]'s parameter tables.
pub trait SubModel: Sized {
    /// This model with its parameters from `contact`.
    fn from_contact(contact: &ContactConfig) -> Self;
    /// Whether `contact` chooses this model (always, for the run-time choice of the kind's models).
    fn chosen(contact: &ContactConfig) -> bool;
}

impl<N: SubModel, D: SubModel, T: SubModel> Composed<N, D, T> {
    /// The law of `contact`'s models (whichever they are) with its parameters.
    pub fn from_contact(contact: &ContactConfig) -> Self {
        Self {
            normal: N::from_contact(contact),
            damping: D::from_contact(contact),
            tangential: T::from_contact(contact),
        }
    }
}

impl<N, D, T> RegisteredLaw for Composed<N, D, T>
where
    N: SubModel + NormalModel,
    D: SubModel + DampingModel,
    T: SubModel + TangentialModel,
{
    fn chosen_in(contact: &ContactConfig) -> Option<Self> {
        (N::chosen(contact) && D::chosen(contact) && T::chosen(contact)).then(|| Self::from_contact(contact))
    }
}

/// The per-contact state of a normal spring chosen at run time: the number its own state is
/// ([`ContactState::to_number`]; 0 for a spring without state).
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct AnyState(pub f64);

impl ContactState for AnyState {
    fn to_number(self) -> f64 {
        self.0
    }
    fn from_number(value: f64) -> Self {
        Self(value)
    }
}

/// Which normal spring (`contact.normal`).
#[derive(Clone, Copy, Debug, PartialEq, Eq, Serialize, Deserialize)]
#[serde(rename_all = "snake_case")]
pub enum NormalKind {
    /// Hertz spring `F = 4/3 E* √R* δ^{3/2}` (eqs 6, 8), from the materials' constants.
    Hertz,
    /// Linear spring `F = k_n δ`.
    Linear,
    /// Hysteretic linear spring (Walton-Braun): plastic loading, stiffer elastic unloading.
    HystereticLinear,
}

/// Which damping (`contact.damping`).
#[derive(Clone, Copy, Debug, PartialEq, Eq, Serialize, Deserialize)]
#[serde(rename_all = "snake_case")]
pub enum DampingKind {
    /// The paper's `2√(5/6) β √(S m*)` (eqs 7, 12).
    Paper,
    /// Viscous at damping ratio β, `2 β √(S m*)`.
    Viscous,
    /// Viscoelastic (Kuwabara-Kono), `A S` with a dissipation time A.
    Viscoelastic,
}

/// Which tangential spring (`contact.tangential`).
#[derive(Clone, Copy, Debug, PartialEq, Eq, Serialize, Deserialize)]
#[serde(rename_all = "snake_case")]
pub enum TangentialKind {
    /// Mindlin's `S_t = 8 G* √(R* δ)` (eq 11, fixed), with the Hertz spring.
    Mindlin,
    /// A fixed fraction of the normal stiffness (the normal spring's `tangential_stiffness_ratio`).
    Linear,
}

/// Which rolling resistance (`contact.rolling`).
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Serialize, Deserialize)]
#[serde(rename_all = "snake_case")]
pub enum RollingKind {
    /// EDEM's constant directional torque `μ0 F_n R` (the default).
    #[default]
    ConstantTorque,
    /// None, whatever the rolling friction.
    None,
}

/// Which preset law (`contact.law`): a normal spring, a damping and a tangential spring.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Serialize, Deserialize)]
#[serde(rename_all = "snake_case")]
pub enum ContactLawKind {
    /// The paper's Hertz-Mindlin law with the spec's fixes (the default).
    #[default]
    HertzMindlin,
    /// Linear spring-dashpot (Cundall-Strack) with Coulomb friction.
    Linear,
    /// Hysteretic linear spring (Walton-Braun) with the linear law's dashpot and tangential spring.
    HystereticLinear,
}

/// Any normal spring, chosen when the law is built (for compositions no preset has).
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum AnyNormal {
    /// [`NormalKind::Hertz`].
    Hertz(HertzNormal),
    /// [`NormalKind::Linear`].
    Linear(LinearNormal),
    /// [`NormalKind::HystereticLinear`].
    HystereticLinear(HystereticNormal),
}

/// Any damping, chosen when the law is built (for compositions no preset has).
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum AnyDamping {
    /// [`DampingKind::Paper`].
    Paper(PaperDamping),
    /// [`DampingKind::Viscous`].
    Viscous(ViscousDamping),
    /// [`DampingKind::Viscoelastic`].
    Viscoelastic(ViscoelasticDamping),
}

/// Any tangential spring, chosen when the law is built (for compositions no preset has).
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum AnyTangential {
    /// [`TangentialKind::Mindlin`].
    Mindlin(MindlinTangential),
    /// [`TangentialKind::Linear`].
    Linear(LinearTangential),
}

/// Any rolling resistance, chosen when the law is built (for compositions no preset has).
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum AnyRolling {
    /// [`RollingKind::ConstantTorque`].
    ConstantTorque(ConstantTorque),
    /// [`RollingKind::None`].
    None(NoRolling),
}

/// `[contact]`: the law (a preset) and the sub-models that replace the preset's, the options every
/// law shares, and each model's parameters in a table of its own (`[contact.linear]`, …), so that a
/// sweep may switch models.
#[derive(Clone, Debug, Default, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields, default)]
pub struct ContactConfig {
    /// The force law: a preset of normal spring, damping and tangential spring.
    pub law: ContactLawKind,
    /// The normal spring, replacing the law's.
    pub normal: Option<NormalKind>,
    /// The damping of both springs, replacing the law's.
    pub damping: Option<DampingKind>,
    /// The tangential spring, replacing the law's.
    pub tangential: Option<TangentialKind>,
    /// The rolling resistance.
    pub rolling: RollingKind,
    /// Allow a tensile (attractive) normal force from damping instead of clamping `Fn ≥ 0`.
    pub allow_tension: bool,
    /// Parameters of `hertz_mindlin`.
    pub hertz_mindlin: NoParameters,
    /// Parameters of `hertz`.
    pub hertz: HertzNormal,
    /// Parameters of `linear`.
    pub linear: LinearNormal,
    /// Parameters of `hysteretic_linear`.
    pub hysteretic_linear: HystereticNormal,
    /// Parameters of `viscoelastic`.
    pub viscoelastic: ViscoelasticDamping,
}

// The rows: `Variant(name[, table]): Type`, the variant of the kind's enum and of its `Any*` enum
// above, the name its key takes, the `ContactConfig` field of its parameters when it has any.
contact_models! {
    normal {
        Hertz(hertz, hertz): HertzNormal,
        Linear(linear, linear): LinearNormal,
        HystereticLinear(hysteretic_linear, hysteretic_linear): HystereticNormal,
    }
    damping {
        Paper(paper): PaperDamping,
        Viscous(viscous): ViscousDamping,
        Viscoelastic(viscoelastic, viscoelastic): ViscoelasticDamping,
    }
    tangential {
        Mindlin(mindlin): MindlinTangential,
        Linear(linear): LinearTangential,
    }
    rolling {
        ConstantTorque(constant_torque): ConstantTorque,
        None(none): NoRolling,
    }
    presets {
        /// The paper's Hertz-Mindlin law with the spec's fixes (the default).
        HertzMindlin(hertz_mindlin, hertz_mindlin): HertzMindlin = HertzNormal + PaperDamping + MindlinTangential,
        /// Linear spring-dashpot (Cundall-Strack) with Coulomb friction.
        Linear(linear): LinearSpringDashpot = LinearNormal + ViscousDamping + LinearTangential,
        /// Hysteretic linear spring (Walton-Braun) with the linear law's dashpot and tangential spring.
        HystereticLinear(hysteretic_linear): HystereticLinear = HystereticNormal + ViscousDamping + LinearTangential,
    }
}

/// The law of a composition no preset has: every model chosen when the law is built.
pub type AnyLaw = Composed<AnyNormal, AnyDamping, AnyTangential>;

/// The table of a preset whose models take their parameters from their own tables: empty, kept so
/// that files that list it stay valid.
#[derive(Clone, Copy, Debug, Default, PartialEq, Serialize, Deserialize, SceneKeys)]
#[serde(deny_unknown_fields)]
pub struct NoParameters {}

/// The models of a law.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct Composition {
    /// The normal spring.
    pub normal: NormalKind,
    /// The damping of both springs.
    pub damping: DampingKind,
    /// The tangential spring.
    pub tangential: TangentialKind,
}

impl ContactConfig {
    /// The scene's normal spring: `normal`, else the law's.
    pub fn normal_kind(&self) -> NormalKind {
        self.normal.unwrap_or(self.law.composition().normal)
    }

    /// The scene's damping: `damping`, else the law's.
    pub fn damping_kind(&self) -> DampingKind {
        self.damping.unwrap_or(self.law.composition().damping)
    }

    /// The scene's tangential spring: `tangential`, else the law's.
    pub fn tangential_kind(&self) -> TangentialKind {
        self.tangential.unwrap_or(self.law.composition().tangential)
    }

    /// The scene's rolling resistance.
    pub fn rolling_kind(&self) -> RollingKind {
        self.rolling
    }

    /// The scene's models.
    pub fn composition(&self) -> Composition {
        Composition { normal: self.normal_kind(), damping: self.damping_kind(), tangential: self.tangential_kind() }
    }

    /// The preset whose models the scene's are, if one is.
    pub fn preset(&self) -> Option<ContactLawKind> {
        let composition = self.composition();
        ContactLawKind::ALL.iter().copied().find(|law| law.composition() == composition)
    }

    /// The law's name for reports: its preset's, else its models' (`linear+paper+linear`).
    pub fn law_name(&self) -> String {
        match self.preset() {
            Some(law) => law.name().to_string(),
            None => {
                let c = self.composition();
                format!("{}+{}+{}", c.normal.name(), c.damping.name(), c.tangential.name())
            }
        }
    }

    /// The rolling-resistance coefficient `c` (moment `c F_n R`) of a material of rolling friction μ0.
    pub fn rolling_coefficient(&self, rolling_friction: f64) -> f64 {
        AnyRolling::from_contact(self).coefficient(rolling_friction)
    }

    /// Problems with the chosen models' parameters and with their combination, and non-finite
    /// numbers in any model's table, chosen or not (the scene keeps every table), as (full key,
    /// reason).
    pub fn problems(&self) -> Vec<(String, String)> {
        let mut problems = self.chosen_problems();
        let reported: Vec<String> = problems.iter().map(|(key, _)| key.clone()).collect();
        problems.extend(self.non_finite().into_iter().filter(|(key, _)| !reported.contains(key)));
        problems
    }

    /// Every number of the models' tables that is not finite, as (full key, reason).
    fn non_finite(&self) -> Vec<(String, String)> {
        let Ok(toml::Value::Table(tables)) = toml::Value::try_from(self) else { return Vec::new() };
        let numbers = tables.iter().filter_map(|(table, keys)| Some((table, keys.as_table()?)));
        let numbers = numbers.flat_map(|(table, keys)| keys.iter().map(move |(key, value)| (table, key, value)));
        numbers
            .filter_map(|(table, key, value)| {
                let x = value.as_float().filter(|x| !x.is_finite())?;
                Some((format!("contact.{table}.{key}"), format!("must be a finite number, got {}", exact(x))))
            })
            .collect()
    }

    /// Problems with the chosen models' parameters and with their combination.
    fn chosen_problems(&self) -> Vec<(String, String)> {
        let c = self.composition();
        let normal = AnyNormal::from_contact(self);
        let in_table = |table: Option<&str>, problems: Problems| {
            let table = table.unwrap_or("?").to_string();
            problems.into_iter().map(move |(key, reason)| (format!("contact.{table}.{key}"), reason))
        };
        let mut problems: Vec<_> = in_table(c.normal.table(), normal.problems()).collect();
        problems.extend(in_table(c.damping.table(), AnyDamping::from_contact(self).problems()));
        if let Some(reason) = AnyTangential::from_contact(self).unfit_with(&normal) {
            let (tangential, spring) = (c.tangential.name(), c.normal.name());
            problems.push((
                "contact.tangential".to_string(),
                format!("\"{tangential}\" {reason}; contact.normal is \"{spring}\" (with it use \"linear\")"),
            ));
        }
        problems
    }
}

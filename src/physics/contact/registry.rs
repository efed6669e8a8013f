//! How the table of contact models ([`super::table`]) is read: `contact_models!` turns its rows
//! into the implementations the declarations of `table.rs` need: each kind's `ALL`, `NAMES`,
//! `name()` and `table()`, each model's `KIND` and [`SubModel`](super::table::SubModel), the run-time
//! choices' model traits, the presets' laws, [`ContactConfig`](super::table::ContactConfig)'s keys
//! and its one dispatch from configuration to law. Every caller that needs the scene's law (the
//! simulation, time-step and stability estimates, tune's screen, benchmarks) goes through that
//! dispatch, so a model added to the table is used everywhere. The implementations match every
//! variant of the declared enums: a row without its variant, or a variant without its row, does not
//! compile.
//!
//! `contact.law` is a preset: it names a normal spring, a damping and a tangential spring; each of
//! `contact.normal`, `contact.damping` and `contact.tangential` that is given replaces the preset's.
//! A composition that is a preset runs that preset's compiled law (a [`Composed`](super::Composed)
//! of the models' own types); any other runs [`AnyLaw`](super::table::AnyLaw), whose models are
//! chosen when the law is built.

/// A model's parameters from `contact`: its table, or its defaults when it has none.
macro_rules! parameters {
    ($contact:ident, $ty:ty) => {{
        let _ = $contact;
        <$ty>::default()
    }};
    ($contact:ident, $ty:ty, $table:ident) => {
        $contact.$table
    };
}

/// The name of a model's parameter table, if it has one.
macro_rules! table_name {
    () => {
        None
    };
    ($table:ident) => {
        Some(stringify!($table))
    };
}

/// The implementations for the rows of one kind: the kind's enum (`$kind`), the run-time choice
/// among them (`$any`) and each row's [`SubModel`](super::table::SubModel) (`$choice`: the
/// [`ContactConfig`](super::table::ContactConfig) method that says which the scene has).
macro_rules! model_kind {
    ($kind:ident, $any:ident, $choice:ident, $($variant:ident($name:ident $(, $table:ident)?): $ty:ty,)+) => {
        impl $kind {
            /// Every model of the kind, in table order.
            pub const ALL: &[Self] = &[$(Self::$variant,)+];
            /// Their names, as the key takes them.
            pub const NAMES: &[&str] = &[$(stringify!($name),)+];

            /// The model's name, as the key takes it.
            pub fn name(self) -> &'static str {
                match self {
                    $(Self::$variant => stringify!($name),)+
                }
            }

            /// The `[contact.<table>]` of the model's parameters, if it has any.
            pub fn table(self) -> Option<&'static str> {
                match self {
                    $(Self::$variant => $crate::physics::contact::registry::table_name!($($table)?),)+
                }
            }
        }

        $(
            impl $ty {
                /// The model's row of the table.
                pub const KIND: $kind = $kind::$variant;
            }

            impl SubModel for $ty {
                fn from_contact(contact: &ContactConfig) -> Self {
                    $crate::physics::contact::registry::parameters!(contact, $ty $(, $table)?)
                }
                fn chosen(contact: &ContactConfig) -> bool {
                    contact.$choice() == Self::KIND
                }
            }
        )+

        impl SubModel for $any {
            fn from_contact(contact: &ContactConfig) -> Self {
                match contact.$choice() {
                    $($kind::$variant => Self::$variant(<$ty as SubModel>::from_contact(contact)),)+
                }
            }
            fn chosen(_: &ContactConfig) -> bool {
                true
            }
        }
    };
}

/// The table: each kind's rows (`Variant(name[, table]): Type`, `table` the
/// [`ContactConfig`](super::table::ContactConfig) field of its parameters when it has any), the
/// rolling rows, then the presets (`Variant(name[, table]): Alias = Normal + Damping + Tangential`).
/// Makes the kinds' implementations (`model_kind!`), the run-time choices' sub-model traits,
/// `ContactLawKind`'s, the preset laws' type aliases, and [`ContactConfig`](super::table::ContactConfig)'s
/// keys and dispatch.
macro_rules! contact_models {
    (
        normal { $($nv:ident($nname:ident $(, $ntable:ident)?): $nty:ty,)+ }
        damping { $($dv:ident($dname:ident $(, $dtable:ident)?): $dty:ty,)+ }
        tangential { $($tv:ident($tname:ident $(, $ttable:ident)?): $tty:ty,)+ }
        rolling { $($rv:ident($rname:ident $(, $rtable:ident)?): $rty:ty,)+ }
        presets {
            $($(#[doc = $pdoc:literal])* $pv:ident($pname:ident $(, $ptable:ident)?): $alias:ident = $pn:ident + $pd:ident + $pt:ident,)+
        }
    ) => {
        $crate::physics::contact::registry::model_kind!(NormalKind, AnyNormal, normal_kind,
            $($nv($nname $(, $ntable)?): $nty,)+);
        $crate::physics::contact::registry::model_kind!(DampingKind, AnyDamping, damping_kind,
            $($dv($dname $(, $dtable)?): $dty,)+);
        $crate::physics::contact::registry::model_kind!(TangentialKind, AnyTangential, tangential_kind,
            $($tv($tname $(, $ttable)?): $tty,)+);
        $crate::physics::contact::registry::model_kind!(RollingKind, AnyRolling, rolling_kind,
            $($rv($rname $(, $rtable)?): $rty,)+);

        impl NormalModel for AnyNormal {
            type State = AnyState;

            #[inline(always)]
            fn load(&self, p: &PairProperties, overlap: f64, state: &mut AnyState) -> (f64, Stiffness) {
                match self {
                    $(Self::$nv(model) => {
                        let mut own = <<$nty as NormalModel>::State as ContactState>::from_number(state.0);
                        let load = model.load(p, overlap, &mut own);
                        state.0 = own.to_number();
                        load
                    })+
                }
            }
            fn elastic_energy(&self, p: &PairProperties, overlap: f64, state: &AnyState) -> f64 {
                match self {
                    $(Self::$nv(model) => model.elastic_energy(p, overlap, &ContactState::from_number(state.0)),)+
                }
            }
            fn tangential_stiffness_ratio(&self) -> f64 {
                match self {
                    $(Self::$nv(model) => model.tangential_stiffness_ratio(),)+
                }
            }
            fn hertzian(&self) -> bool {
                match self {
                    $(Self::$nv(model) => model.hertzian(),)+
                }
            }
            fn problems(&self) -> Problems {
                match self {
                    $(Self::$nv(model) => model.problems(),)+
                }
            }
        }

        impl DampingModel for AnyDamping {
            #[inline(always)]
            fn coefficient(&self, p: &PairProperties, spring: Stiffness) -> f64 {
                match self {
                    $(Self::$dv(model) => model.coefficient(p, spring),)+
                }
            }
            fn problems(&self) -> Problems {
                match self {
                    $(Self::$dv(model) => model.problems(),)+
                }
            }
        }

        impl TangentialModel for AnyTangential {
            #[inline(always)]
            fn stiffness<N: NormalModel>(&self, normal: &N, p: &PairProperties, overlap: f64, s: Stiffness) -> Stiffness {
                match self {
                    $(Self::$tv(model) => model.stiffness(normal, p, overlap, s),)+
                }
            }
            fn unfit_with<N: NormalModel>(&self, normal: &N) -> Option<&'static str> {
                match self {
                    $(Self::$tv(model) => model.unfit_with(normal),)+
                }
            }
        }

        impl RollingModel for AnyRolling {
            fn coefficient(&self, rolling_friction: f64) -> f64 {
                match self {
                    $(Self::$rv(model) => model.coefficient(rolling_friction),)+
                }
            }
        }

        $($(#[doc = $pdoc])* pub type $alias = Composed<$pn, $pd, $pt>;)+

        impl ContactLawKind {
            /// Every preset, in table order.
            pub const ALL: &[Self] = &[$(Self::$pv,)+];
            /// Their names, as `contact.law` takes them.
            pub const NAMES: &[&str] = &[$(stringify!($pname),)+];

            /// The preset's name, as `contact.law` takes it.
            pub fn name(self) -> &'static str {
                match self {
                    $(Self::$pv => stringify!($pname),)+
                }
            }

            /// The models the preset composes.
            pub fn composition(self) -> Composition {
                match self {
                    $(Self::$pv => Composition { normal: <$pn>::KIND, damping: <$pd>::KIND, tangential: <$pt>::KIND },)+
                }
            }
        }

        impl ContactConfig {
            /// The `[contact]` keys (`physics::keys`): the choices, the shared option, each table.
            pub const KEYS: &'static [KeyDoc] = &[
                KeyDoc {
                    name: "law",
                    doc: &["The force law: a preset of `normal`, `damping` and `tangential`, which replace its own when given."],
                    spec: KeySpec { one_of: ContactLawKind::NAMES, ..KeySpec::NONE },
                },
                KeyDoc {
                    name: "normal",
                    doc: &["The normal spring; none: the law's."],
                    spec: KeySpec { one_of: NormalKind::NAMES, ..KeySpec::NONE },
                },
                KeyDoc {
                    name: "damping",
                    doc: &["The damping of both springs; none: the law's."],
                    spec: KeySpec { one_of: DampingKind::NAMES, ..KeySpec::NONE },
                },
                KeyDoc {
                    name: "tangential",
                    doc: &["The tangential spring (with the Coulomb cap); none: the law's."],
                    spec: KeySpec { one_of: TangentialKind::NAMES, ..KeySpec::NONE },
                },
                KeyDoc {
                    name: "rolling",
                    doc: &["The rolling resistance."],
                    spec: KeySpec { one_of: RollingKind::NAMES, ..KeySpec::NONE },
                },
                KeyDoc {
                    name: "allow_tension",
                    doc: &["Allow a tensile (attractive) normal force from damping instead of clamping `Fn ≥ 0`."],
                    spec: KeySpec { range: "true or false", ..KeySpec::NONE },
                },
                $($(KeyDoc { name: stringify!($ptable), doc: &[concat!("Parameters of `", stringify!($pname), "`.")], spec: KeySpec { table: Some(NoParameters::KEYS), ..KeySpec::NONE } },)?)+
                $($(KeyDoc { name: stringify!($ntable), doc: &[concat!("Parameters of `", stringify!($nname), "`.")], spec: KeySpec { table: Some(<$nty>::KEYS), ..KeySpec::NONE } },)?)+
                $($(KeyDoc { name: stringify!($dtable), doc: &[concat!("Parameters of `", stringify!($dname), "`.")], spec: KeySpec { table: Some(<$dty>::KEYS), ..KeySpec::NONE } },)?)+
                $($(KeyDoc { name: stringify!($ttable), doc: &[concat!("Parameters of `", stringify!($tname), "`.")], spec: KeySpec { table: Some(<$tty>::KEYS), ..KeySpec::NONE } },)?)+
                $($(KeyDoc { name: stringify!($rtable), doc: &[concat!("Parameters of `", stringify!($rname), "`.")], spec: KeySpec { table: Some(<$rty>::KEYS), ..KeySpec::NONE } },)?)+
            ];

            /// Runs `visitor` with the scene's law: the one dispatch from configuration to law. A
            /// preset's composition runs the preset's own compiled law, any other [`AnyLaw`](super::table::AnyLaw).
            pub fn dispatch<V: LawVisitor>(&self, visitor: V) -> V::Output {
                match self.preset() {
                    $(Some(ContactLawKind::$pv) => visitor.visit(&<$alias>::from_contact(self)),)+
                    None => visitor.visit(&AnyLaw::from_contact(self)),
                }
            }
        }
    };
}

pub(super) use {contact_models, model_kind, parameters, table_name};

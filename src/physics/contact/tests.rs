//! The table's keys, presets and checks, and the run-time composition against the compiled ones.

use super::*;

#[test]
fn every_name_is_the_serde_name_and_every_table_a_field() {
    fn check<K: serde::Serialize + Copy>(all: &[K], names: &[&str], table: impl Fn(K) -> Option<&'static str>) {
        let contact = toml::Value::try_from(ContactConfig::default()).expect("serialises");
        for (&kind, &name) in all.iter().zip(names) {
            assert_eq!(toml::Value::try_from(kind).expect("a name").as_str(), Some(name));
            if let Some(table) = table(kind) {
                assert!(contact.get(table).is_some_and(toml::Value::is_table), "[contact.{table}]");
            }
        }
        assert_eq!(all.len(), names.len());
    }
    check(NormalKind::ALL, NormalKind::NAMES, NormalKind::table);
    check(DampingKind::ALL, DampingKind::NAMES, DampingKind::table);
    check(TangentialKind::ALL, TangentialKind::NAMES, TangentialKind::table);
    check(RollingKind::ALL, RollingKind::NAMES, RollingKind::table);
    check(ContactLawKind::ALL, ContactLawKind::NAMES, |_| None);
}

#[test]
fn the_law_is_a_preset_that_the_model_keys_override() {
    let parse = |text: &str| -> ContactConfig { toml::from_str(text).expect("a [contact] table") };
    let c = parse("law = \"linear\"");
    let linear =
        Composition { normal: NormalKind::Linear, damping: DampingKind::Viscous, tangential: TangentialKind::Linear };
    assert_eq!((c.composition(), c.preset(), c.law_name().as_str()), (linear, Some(ContactLawKind::Linear), "linear"));
    // Given keys replace the preset's models, and a composition that is a preset is that preset.
    let c = parse("law = \"hertz_mindlin\"\nnormal = \"linear\"\ntangential = \"linear\"\ndamping = \"viscous\"");
    assert_eq!(c.preset(), Some(ContactLawKind::Linear));
    let c = parse("law = \"linear\"\ndamping = \"paper\"");
    assert_eq!((c.preset(), c.law_name().as_str()), (None, "linear+paper+linear"));
    assert_eq!(c.normal_kind(), NormalKind::Linear);
    assert!(toml::from_str::<ContactConfig>("damping = \"tsuji_typo\"").is_err());
}

#[test]
fn meaningless_combinations_and_bad_parameters_are_named_by_key() {
    let mut c = ContactConfig { normal: Some(NormalKind::Linear), ..Default::default() };
    let problems = c.problems();
    assert_eq!(problems.len(), 1, "{problems:?}");
    assert_eq!(problems[0].0, "contact.tangential");
    assert!(problems[0].1.contains("\"mindlin\"") && problems[0].1.contains("\"linear\""), "{problems:?}");
    c.tangential = Some(TangentialKind::Linear);
    assert!(c.problems().is_empty());
    c.damping = Some(DampingKind::Viscoelastic);
    c.viscoelastic.dissipation_time = -1.0;
    c.linear.normal_stiffness = Some(0.0);
    let keys: Vec<String> = c.problems().into_iter().map(|(key, _)| key).collect();
    assert_eq!(keys, ["contact.linear.normal_stiffness", "contact.viscoelastic.dissipation_time"]);
    // A model's table is checked only when the model is chosen.
    c.damping = Some(DampingKind::Paper);
    assert_eq!(c.problems().len(), 1);
}

/// The coefficients of `law` along a load-unload cycle, as bits.
fn cycle<L: ContactLaw>(law: &L, pair: &PairProperties) -> Vec<u64> {
    let mut state = L::State::default();
    [1e-5, 4e-5, 9e-5, 6e-5, 2e-5, 8e-5, 1.2e-4]
        .iter()
        .flat_map(|&overlap| {
            let c = law.coefficients(pair, overlap, &mut state);
            let energy = law.normal_elastic_energy(pair, overlap, &state);
            [c.normal_force, c.normal_damping, c.tangential_stiffness, c.tangential_damping, energy]
        })
        .map(f64::to_bits)
        .collect()
}

#[test]
fn the_run_time_composition_of_a_preset_gives_the_presets_bits() {
    struct Bits<'a>(&'a PairProperties);
    impl LawVisitor for Bits<'_> {
        type Output = Vec<u64>;
        fn visit<L: RegisteredLaw>(self, law: &L) -> Vec<u64> {
            cycle(law, self.0)
        }
    }
    let pair = PairProperties { e_star: 5e8, g_star: 2e8, r_star: 0.004, m_star: 0.02, beta: 0.3 };
    for &law in ContactLawKind::ALL {
        let contact = ContactConfig { law, ..Default::default() };
        let compiled = contact.dispatch(Bits(&pair));
        assert_eq!(cycle(&AnyLaw::from_contact(&contact), &pair), compiled, "{law:?}");
        assert!(AnyLaw::chosen_in(&contact).is_some());
    }
    let linear = ContactConfig { law: ContactLawKind::Linear, ..Default::default() };
    assert!(HertzMindlin::chosen_in(&linear).is_none() && LinearSpringDashpot::chosen_in(&linear).is_some());
}

#[test]
fn the_rolling_model_sets_the_moment_coefficient() {
    let mut c = ContactConfig::default();
    assert_eq!(c.rolling_coefficient(0.3), 0.3);
    c.rolling = RollingKind::None;
    assert_eq!(c.rolling_coefficient(0.3), 0.0);
}

use constraint_stabilization::settings::{LineSearchSettings, Settings};

#[test]
fn the_builder_sets_each_field_and_names_the_invalid_one() {
    let settings = Settings::builder()
        .tolerance_absolute(1e-4)
        .max_passes(7)
        .build()
        .expect("valid");
    assert_eq!(settings.tolerance_absolute, Some(1e-4));
    assert_eq!(settings.max_passes, 7);
    let error = Settings::builder()
        .line_search(LineSearchSettings {
            shrink: 1.5,
            ..LineSearchSettings::default()
        })
        .build()
        .expect_err("shrink out of range");
    assert_eq!(error.field(), "line_search.shrink");
    assert!(error.to_string().contains("line_search.shrink"));
}

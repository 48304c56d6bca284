use constraint_stabilization::settings::GaussSeidelSettings;

#[test]
fn defaults_are_box2d_and_valid() {
    let settings = GaussSeidelSettings::default();
    assert_eq!(settings.iterations, 3);
    assert_eq!(settings.baumgarte, 0.2);
    assert_eq!(settings.slop_relative, 0.005);
    assert_eq!(settings.max_correction_relative, 0.2);
    assert_eq!(settings.validate(), Ok(()));
}

#[test]
fn each_invalid_field_has_its_error() {
    let field_of = |change: fn(&mut GaussSeidelSettings)| {
        let mut settings = GaussSeidelSettings::default();
        change(&mut settings);
        settings.validate().err().map(|e| e.field())
    };
    let baumgarte = Some("gauss_seidel.baumgarte");
    assert_eq!(
        field_of(|s| s.iterations = 0),
        Some("gauss_seidel.iterations")
    );
    assert_eq!(field_of(|s| s.baumgarte = 0.0), baumgarte);
    assert_eq!(field_of(|s| s.baumgarte = 1.5), baumgarte);
    assert_eq!(field_of(|s| s.baumgarte = f64::NAN), baumgarte);
    let slop = Some("gauss_seidel.slop_relative");
    assert_eq!(field_of(|s| s.slop_relative = -1e-3), slop);
    assert_eq!(field_of(|s| s.slop_relative = f64::INFINITY), slop);
    let cap = Some("gauss_seidel.max_correction_relative");
    assert_eq!(field_of(|s| s.max_correction_relative = 0.0), cap);
    assert_eq!(field_of(|s| s.max_correction_relative = f64::NAN), cap);
    assert_eq!(
        field_of(|s| s.max_correction_relative = f64::INFINITY),
        None
    );
    assert_eq!(field_of(|s| s.baumgarte = 1.0), None);
}

use constraint_stabilization::Settings;

#[test]
fn relative_lengths_scale_and_absolute_ones_override() {
    let mut settings = Settings::default();
    let lengths = settings.resolve(2.0);
    assert_eq!(lengths.tolerance, 2e-6);
    assert_eq!(lengths.contact_margin, 2e-2);
    assert_eq!(lengths.gauss_seidel_slop, 0.01);
    assert_eq!(lengths.gauss_seidel_max_correction, 0.4);
    settings.tolerance_absolute = Some(1e-3);
    settings.allowed_penetration = 1e-4;
    let lengths = settings.resolve(2.0);
    assert_eq!(lengths.tolerance, 1e-3 + 1e-4);
    assert_eq!(
        lengths.target_margin,
        2.0 * settings.target_margin_relative - 1e-4
    );
}

//! Every packing spec under examples/ parses and validates.

#[test]
fn example_specs_validate() {
    let dir = std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join("../../examples/xue2019");
    let mut seen = 0;
    for entry in std::fs::read_dir(&dir).expect("examples/xue2019") {
        let path = entry.unwrap().path();
        let name = path.file_name().unwrap().to_string_lossy().to_string();
        if !(name.starts_with("packing_") && name.ends_with(".toml")) {
            continue;
        }
        let text = std::fs::read_to_string(&path).unwrap();
        let spec = grains_pack::parse(&text, &name).unwrap_or_else(|e| panic!("{e}"));
        let v = grains_pack::validate(&spec).unwrap_or_else(|e| panic!("{name}: {e}"));
        assert!(v.estimated_particles > 1e4, "{name}");
        seen += 1;
    }
    assert!(seen >= 6, "only {seen} packing specs found");
}

//! The embedding example runs and writes what it says.

#[path = "../examples/embed.rs"]
mod example;

#[test]
fn the_embedding_example_renders_and_writes_its_image() {
    let dir = std::env::temp_dir().join(format!("fenestra-embed-{}", std::process::id()));
    let exr = dir.join("embedded.exr");
    let stats = example::embed(&exr).expect("the example renders");
    assert_eq!((stats.width, stats.height, stats.spp), (64, 64, 8));
    assert_eq!(stats.integrator, "lp_hf");
    let image = fenestra_core::image::Image::read(&exr).expect("the EXR reads back");
    assert_eq!((image.width, image.height), (64, 64));
    let lit = image
        .pixels
        .iter()
        .filter(|p| p.max_component() > 0.0)
        .count();
    assert!(
        lit > 64 * 64 / 4,
        "the sky lights the room: {lit} lit pixels"
    );
    for companion in ["embedded.png", "embedded.json"] {
        assert!(dir.join(companion).exists(), "{companion} beside the EXR");
    }
    let _ = std::fs::remove_dir_all(&dir);
}

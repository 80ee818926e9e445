//! What the statistics examples share.

/// The built-in many-light scenes.
pub const SCENES: [&str; 5] = [
    "kitchen-72",
    "kitchen-72-env",
    "ponderosa-138",
    "terminal-832",
    "tower",
];

/// The scenes named on the command line, or all of [`SCENES`].
pub fn scene_names() -> Vec<String> {
    let names: Vec<String> = std::env::args().skip(1).collect();
    if names.is_empty() {
        SCENES.map(String::from).to_vec()
    } else {
        names
    }
}

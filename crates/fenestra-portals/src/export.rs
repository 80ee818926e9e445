//! Portals for other tools: OBJ polygons, and pbrt-v4 shapes with the "interface" material
//! (invisible to light, so including the file changes no picture), plus the "point3 portal"
//! parameter of an infinite light for each quad.

use crate::error::PortalError;
use crate::plot::outline;
use crate::portal::Portal;
use fenestra_core::fs::{write_text_atomically, WriteError};
use std::fmt::Write as _;
use std::path::Path;

/// One object per portal, a single polygon each (ellipses as 128-gons).
pub fn obj(portals: &[Portal]) -> String {
    let mut s = String::from("# light portals estimated by fenestra\n");
    let mut base = 1;
    for (k, p) in portals.iter().enumerate() {
        let ring = outline(p);
        let _ = writeln!(s, "o portal_{k}");
        for v in &ring {
            let _ = writeln!(s, "v {} {} {}", v.x, v.y, v.z);
        }
        let face: Vec<String> = (base..base + ring.len()).map(|i| i.to_string()).collect();
        let _ = writeln!(s, "f {}", face.join(" "));
        base += ring.len();
    }
    s
}

/// pbrt-v4 text: each portal a triangle fan under `Material "interface"` (pbrt-v4 and
/// fenestra both let light through it); each quad also as the `"point3 portal"` parameter to
/// paste into an infinite light (pbrt-v4 takes one portal per infinite light).
pub fn pbrt(portals: &[Portal]) -> String {
    let mut s = String::from(
        "# Light portals estimated by fenestra. Include this file inside WorldBegin to see them\n\
         # as invisible \"interface\" shapes; for a sky-lit scene, add a quad's \"point3 portal\"\n\
         # line to the LightSource \"infinite\".\n",
    );
    for (k, p) in portals.iter().enumerate() {
        let ring = outline(p);
        let _ = writeln!(s, "# portal {k}: area {:.6} m^2", p.area());
        if let Portal::Quad { .. } = p {
            let pts: Vec<String> = ring
                .iter()
                .map(|v| format!("{} {} {}", v.x, v.y, v.z))
                .collect();
            let _ = writeln!(s, "#   \"point3 portal\" [ {} ]", pts.join("  "));
        }
        let _ = writeln!(s, "AttributeBegin\n  Material \"interface\"");
        let pts: Vec<String> = ring
            .iter()
            .map(|v| format!("{} {} {}", v.x, v.y, v.z))
            .collect();
        let fan: Vec<String> = (1..ring.len() - 1)
            .map(|i| format!("0 {} {}", i, i + 1))
            .collect();
        let _ = writeln!(
            s,
            "  Shape \"trianglemesh\"\n    \"point3 P\" [ {} ]\n    \"integer indices\" [ {} ]\nAttributeEnd",
            pts.join("  "),
            fan.join("  ")
        );
    }
    s
}

/// Writes `portals` to `path` as OBJ or pbrt by its extension.
pub fn write(portals: &[Portal], path: &Path) -> Result<(), PortalError> {
    let ext = path
        .extension()
        .and_then(|e| e.to_str())
        .map(str::to_ascii_lowercase);
    let text = match ext.as_deref() {
        Some("obj") => obj(portals),
        Some("pbrt") => pbrt(portals),
        _ => return Err(WriteError::new(path, "portals export as .pbrt or .obj").into()),
    };
    Ok(write_text_atomically(path, &text)?)
}

//! The Utah teapot of the command line's example document (Newell's 32 Bezier patches, z up),
//! shared by the examples that draw it.

use std::error::Error;

use splinegpu::surface::{Net, Surface, SurfaceKind};

/// The teapot of the command line's example document.
pub(crate) fn teapot() -> Result<Surface, Box<dyn Error>> {
    let text = include_str!("../../../splinegpu-cli/examples/teapot.json");
    let doc: serde_json::Value = serde_json::from_str(text)?;
    let surface = &doc["surfaces"][0];
    let coords: Vec<f64> = surface["points"]
        .as_array()
        .ok_or("points")?
        .iter()
        .flat_map(|p| {
            p.as_array()
                .into_iter()
                .flatten()
                .filter_map(serde_json::Value::as_f64)
        })
        .collect();
    let patches = surface["patches"]
        .as_array()
        .ok_or("patches")?
        .iter()
        .map(|p| std::array::from_fn(|k| p[k].as_u64().unwrap_or(0) as usize))
        .collect();
    let net = Net::new(3, coords.len() / 3, 1, coords)?;
    Ok(Surface::new(SurfaceKind::BezierPatches { patches }, net)?)
}

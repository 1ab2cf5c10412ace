//! Surface kinds by the contract's names ("bspline", "bezier", "nurbs", ...) with their
//! optional fields: the one table the document parser and the Python bindings build a
//! [`SurfaceKind`] from, as [`kinds`](crate::kinds) is for curves.

use super::SurfaceKind;
use crate::basis::Basis;
use crate::curve::{CurveKind, Ends};
use crate::error::InputError;
use crate::fit::interp::EndCondition;
use crate::fit::tcb::PerPoint;
use crate::kinds::KindFields;

/// The surface kinds by the contract's names, in its order (the uniform families first).
pub const SURFACE_KINDS: [&str; 9] = [
    "bspline",
    "catmull-rom",
    "cardinal",
    "tensioned-bspline",
    "beta",
    "matrix",
    "bezier",
    "interpolating",
    "nurbs",
];

/// A surface kind's optional fields, by the contract's names; `None` where not given (the
/// kind's default applies, or the kind needs none).
#[derive(Clone, Debug, Default, PartialEq)]
pub struct SurfaceFields {
    /// "ends" of the uniform families along u and along v (default "control" both ways).
    pub ends: Option<[Ends; 2]>,
    /// "tension": cardinal (default 0.5), tensioned-bspline (default 1), beta (default 0).
    pub tension: Option<f64>,
    /// "bias" of beta (default 1).
    pub bias: Option<f64>,
    /// "matrix" of matrix (required), row-major.
    pub matrix: Option<[[f64; 4]; 4]>,
    /// "patches" of bezier: 16 control indices per patch (a patch list; without it, a net).
    pub patches: Option<Vec<[usize; 16]>>,
    /// "conditions" of interpolating (required): along u and along v.
    pub conditions: Option<[EndCondition; 2]>,
    /// "u" of interpolating: one parameter per row.
    pub u: Option<Vec<f64>>,
    /// "v" of interpolating: one parameter per column.
    pub v: Option<Vec<f64>>,
    /// "knots_u" of nurbs (required): n_u + 4 knots.
    pub knots_u: Option<Vec<f64>>,
    /// "knots_v" of nurbs (required): n_v + 4 knots.
    pub knots_v: Option<Vec<f64>>,
    /// "weights" of nurbs: one per point, rows outer.
    pub weights: Option<Vec<f64>>,
}

impl SurfaceFields {
    /// The names of the fields given, in the contract's order.
    fn given(&self) -> Vec<&'static str> {
        [
            ("ends", self.ends.is_some()),
            ("tension", self.tension.is_some()),
            ("bias", self.bias.is_some()),
            ("matrix", self.matrix.is_some()),
            ("patches", self.patches.is_some()),
            ("conditions", self.conditions.is_some()),
            ("u", self.u.is_some()),
            ("v", self.v.is_some()),
            ("knots_u", self.knots_u.is_some()),
            ("knots_v", self.knots_v.is_some()),
            ("weights", self.weights.is_some()),
        ]
        .into_iter()
        .filter_map(|(name, given)| given.then_some(name))
        .collect()
    }
}

/// The fields surface kind `name` takes besides "kind", "points" and "sampling" (None for a
/// name that is not a surface kind).
#[must_use]
pub fn surface_kind_fields(name: &str) -> Option<&'static [&'static str]> {
    Some(match name {
        "bspline" | "catmull-rom" => &["ends"],
        "cardinal" | "tensioned-bspline" => &["ends", "tension"],
        "beta" => &["ends", "bias", "tension"],
        "matrix" => &["ends", "matrix"],
        "bezier" => &["patches"],
        "interpolating" => &["conditions", "u", "v"],
        "nurbs" => &["knots_u", "knots_v", "weights"],
        _ => return None,
    })
}

/// The error for a name that is not a surface kind, listing those that are.
#[must_use]
pub fn not_a_surface_kind(name: &str) -> InputError {
    InputError::field(
        "kind",
        format!(
            "is not a surface kind: \"{name}\" (expected one of {})",
            SURFACE_KINDS.join(", ")
        ),
    )
}

/// The error for field `field`, which a `name` surface does not take, listing those it does.
#[must_use]
pub fn not_a_surface_field(name: &str, field: &str) -> InputError {
    let mut allowed = vec!["kind", "points", "sampling"];
    allowed.extend_from_slice(surface_kind_fields(name).unwrap_or(&[]));
    InputError::field(
        field,
        format!(
            "is not a field of a \"{name}\" surface (allowed: {})",
            allowed.join(", ")
        ),
    )
}

impl SurfaceKind {
    /// The surface kind the contract calls `name`, with `fields` (their values are checked
    /// when a [`Surface`](super::Surface) is made of it).
    ///
    /// # Errors
    /// A name that is not a surface kind (field "kind", listing those that are); a field the
    /// kind does not take (listing those it does); "matrix" without its matrix,
    /// "interpolating" without its conditions, "nurbs" without both knot vectors; a basis
    /// parameter the curve rules refuse.
    pub fn named(name: &str, fields: SurfaceFields) -> Result<SurfaceKind, InputError> {
        let Some(allowed) = surface_kind_fields(name) else {
            return Err(not_a_surface_kind(name));
        };
        if let Some(field) = fields.given().into_iter().find(|f| !allowed.contains(f)) {
            return Err(not_a_surface_field(name, field));
        }
        Ok(match name {
            "bezier" => match fields.patches {
                Some(patches) => SurfaceKind::BezierPatches { patches },
                None => SurfaceKind::Bezier,
            },
            "interpolating" => SurfaceKind::Interpolating {
                conditions: fields.conditions.ok_or_else(|| {
                    InputError::field("conditions", "is missing (one per direction: [c_u, c_v])")
                })?,
                u: fields.u,
                v: fields.v,
            },
            "nurbs" => {
                let required = |knots: Option<Vec<f64>>, field: &str| {
                    knots.ok_or_else(|| {
                        InputError::field(
                            field,
                            "is missing (a nurbs surface needs n + 4 per direction)",
                        )
                    })
                };
                SurfaceKind::Nurbs {
                    knots_u: required(fields.knots_u, "knots_u")?,
                    knots_v: required(fields.knots_v, "knots_v")?,
                    weights: fields.weights,
                }
            }
            // The uniform families: the curve kind's basis, one value per field.
            _ => {
                let curve_fields = KindFields {
                    tension: fields.tension.map(PerPoint::All),
                    bias: fields.bias.map(PerPoint::All),
                    matrix: fields.matrix,
                    ..KindFields::default()
                };
                let basis: Basis = match CurveKind::named(name, curve_fields)? {
                    CurveKind::Uniform { basis, .. } => basis,
                    other => unreachable!("\"{name}\" is a uniform curve kind, not {other:?}"),
                };
                SurfaceKind::Uniform {
                    basis,
                    ends: fields.ends.unwrap_or([Ends::Control; 2]),
                }
            }
        })
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn every_surface_kind_has_its_fields_and_is_named() {
        for name in SURFACE_KINDS {
            assert!(surface_kind_fields(name).is_some(), "{name}");
        }
        let fields = SurfaceFields {
            tension: Some(0.25),
            ends: Some([Ends::Closed, Ends::Repeat]),
            ..SurfaceFields::default()
        };
        assert_eq!(
            SurfaceKind::named("cardinal", fields).unwrap(),
            SurfaceKind::Uniform {
                basis: Basis::Cardinal { tension: 0.25 },
                ends: [Ends::Closed, Ends::Repeat]
            }
        );
        assert_eq!(
            SurfaceKind::named("bezier", SurfaceFields::default()).unwrap(),
            SurfaceKind::Bezier
        );
    }

    #[test]
    fn a_field_the_kind_does_not_take_is_named_with_those_it_does() {
        let fields = SurfaceFields {
            knots_u: Some(vec![0.0; 8]),
            ..SurfaceFields::default()
        };
        let e = SurfaceKind::named("bspline", fields).unwrap_err();
        assert_eq!(e.field.as_deref(), Some("knots_u"));
        assert!(
            e.message.contains("allowed: kind, points, sampling, ends"),
            "{e}"
        );
        let e = SurfaceKind::named("nurbs", SurfaceFields::default()).unwrap_err();
        assert_eq!(e.field.as_deref(), Some("knots_u"));
        let e = SurfaceKind::named("spline", SurfaceFields::default()).unwrap_err();
        assert!(e.message.contains("expected one of bspline"), "{e}");
    }
}

//! Curve kinds by the names the CLI contract gives them ("catmull-rom", "natural", ...), with
//! their optional fields: the one table the document parser and other front ends (the Python
//! bindings) build a [`CurveKind`] from.

use crate::basis::Basis;
use crate::curve::{CurveKind, Ends};
use crate::error::InputError;
use crate::fit::hermite::HermiteSlopes;
use crate::fit::interp::EndCondition;
use crate::fit::tcb::{PerPoint, Tcb};

/// Every kind the contract names, in its order.
pub const KIND_NAMES: [&str; 16] = [
    "cardinal",
    "catmull-rom",
    "bspline",
    "tensioned-bspline",
    "beta",
    "matrix",
    "bezier",
    "natural",
    "clamped",
    "periodic",
    "not-a-knot",
    "hermite",
    "pchip",
    "akima",
    "kochanek-bartels",
    "nurbs",
];

/// A kind's optional fields, by the contract's names; `None` where not given (the kind's
/// default applies, or the kind needs none).
#[derive(Clone, Debug, Default, PartialEq)]
pub struct KindFields {
    /// "ends" of the uniform families (default "control").
    pub ends: Option<Ends>,
    /// "tension": cardinal (default 0.5), tensioned-bspline (default 1), a number; beta
    /// (default 0), a number or one per joint; kochanek-bartels (default 0), a number or one
    /// per point.
    pub tension: Option<PerPoint>,
    /// "bias": beta (default 1), a number or one per joint; kochanek-bartels (default 0), a
    /// number or one per point.
    pub bias: Option<PerPoint>,
    /// "continuity" of kochanek-bartels (default 0): a number or one per point.
    pub continuity: Option<PerPoint>,
    /// "matrix" of matrix (required), row-major.
    pub matrix: Option<[[f64; 4]; 4]>,
    /// "t" of the interpolating kinds: one parameter per point (default 0, 1, ..., n − 1).
    pub t: Option<Vec<f64>>,
    /// "start_derivative" of clamped (required).
    pub start_derivative: Option<Vec<f64>>,
    /// "end_derivative" of clamped (required).
    pub end_derivative: Option<Vec<f64>>,
    /// "tangents" of hermite (required): dP/dt at each point, D values per point, flat.
    pub tangents: Option<Vec<f64>>,
    /// "method" of akima: "akima" (default) or "makima".
    pub method: Option<String>,
    /// "knots" of nurbs (required): n + 4 non-decreasing values.
    pub knots: Option<Vec<f64>>,
    /// "weights" of nurbs: one per control point (refused for now: rational curves are
    /// planned).
    pub weights: Option<Vec<f64>>,
}

impl KindFields {
    /// The names of the fields given, in the contract's order.
    fn given(&self) -> Vec<&'static str> {
        [
            ("ends", self.ends.is_some()),
            ("tension", self.tension.is_some()),
            ("bias", self.bias.is_some()),
            ("continuity", self.continuity.is_some()),
            ("matrix", self.matrix.is_some()),
            ("t", self.t.is_some()),
            ("start_derivative", self.start_derivative.is_some()),
            ("end_derivative", self.end_derivative.is_some()),
            ("tangents", self.tangents.is_some()),
            ("method", self.method.is_some()),
            ("knots", self.knots.is_some()),
            ("weights", self.weights.is_some()),
        ]
        .into_iter()
        .filter_map(|(name, given)| given.then_some(name))
        .collect()
    }
}

/// The fields kind `name` takes besides "points" and "sampling" (None for an unknown name).
#[must_use]
pub fn kind_fields(name: &str) -> Option<&'static [&'static str]> {
    Some(match name {
        "cardinal" | "tensioned-bspline" => &["ends", "tension"],
        "catmull-rom" | "bspline" => &["ends"],
        "beta" => &["ends", "bias", "tension"],
        "matrix" => &["ends", "matrix"],
        "bezier" => &[],
        "natural" | "periodic" | "not-a-knot" => &["t"],
        "clamped" => &["t", "start_derivative", "end_derivative"],
        "hermite" => &["t", "tangents"],
        "pchip" => &["t"],
        "akima" => &["t", "method"],
        "kochanek-bartels" => &["ends", "tension", "continuity", "bias", "t"],
        "nurbs" => &["knots", "weights"],
        _ => return None,
    })
}

/// The error for field `field`, which a `name` curve does not take.
pub fn not_a_field(name: &str, field: &str) -> InputError {
    let mut allowed = vec!["kind", "points", "sampling"];
    allowed.extend_from_slice(kind_fields(name).unwrap_or(&[]));
    allowed.push("geometry");
    InputError::field(
        field,
        format!(
            "is not a field of a \"{name}\" curve (allowed: {})",
            allowed.join(", ")
        ),
    )
}

impl CurveKind {
    /// The kind the contract calls `name`, with `fields` (its values are checked when a
    /// [`Curve`](crate::Curve) is made of it).
    ///
    /// # Errors
    /// An unknown name (field "kind", listing the names); a field the kind does not take
    /// (listing those it does); "matrix" without its matrix; "clamped" without both end
    /// derivatives; "hermite" without its tangents; an akima "method" other than "akima" or
    /// "makima".
    pub fn named(name: &str, fields: KindFields) -> Result<CurveKind, InputError> {
        let Some(allowed) = kind_fields(name) else {
            return Err(InputError::field(
                "kind",
                format!(
                    "is unknown: \"{name}\" (expected one of {})",
                    KIND_NAMES.join(", ")
                ),
            ));
        };
        if let Some(field) = fields.given().into_iter().find(|f| !allowed.contains(f)) {
            return Err(not_a_field(name, field));
        }
        let ends = fields.ends.unwrap_or_default();
        let uniform = |basis| CurveKind::Uniform { basis, ends };
        let required = |value: Option<Vec<f64>>, field: &str| {
            value.ok_or_else(|| {
                InputError::field(
                    field,
                    "is missing (a clamped spline needs both end derivatives)",
                )
            })
        };
        let interpolating = |condition| CurveKind::Interpolating {
            condition,
            t: fields.t.clone(),
        };
        let hermite = |slopes| CurveKind::Hermite {
            slopes,
            t: fields.t.clone(),
        };
        // The uniform kinds' parameters are numbers; arrays are Kochanek–Bartels'.
        let number = |field: &str, value: &Option<PerPoint>| match value {
            None => Ok(None),
            Some(PerPoint::All(v)) => Ok(Some(*v)),
            Some(PerPoint::Each(_)) => Err(InputError::field(
                field,
                format!("must be a number for a \"{name}\" curve, got an array"),
            )),
        };
        let tension = number("tension", &fields.tension);
        let bias = number("bias", &fields.bias);
        Ok(match name {
            "nurbs" => CurveKind::Nurbs {
                knots: fields.knots.clone().ok_or_else(|| {
                    InputError::field("knots", "is missing (a nurbs curve needs n + 4)")
                })?,
                weights: fields.weights.clone(),
            },
            "kochanek-bartels" => {
                let given = |v: &Option<PerPoint>| v.clone().unwrap_or(PerPoint::All(0.0));
                CurveKind::KochanekBartels {
                    ends,
                    tcb: Tcb {
                        tension: given(&fields.tension),
                        continuity: given(&fields.continuity),
                        bias: given(&fields.bias),
                    },
                    t: fields.t.clone(),
                }
            }
            "hermite" => hermite(HermiteSlopes::Given(fields.tangents.clone().ok_or_else(
                || {
                    InputError::field(
                        "tangents",
                        "is missing (a hermite curve needs one per point)",
                    )
                },
            )?)),
            "pchip" => hermite(HermiteSlopes::Pchip),
            "akima" => hermite(match fields.method.as_deref() {
                None | Some("akima") => HermiteSlopes::Akima,
                Some("makima") => HermiteSlopes::Makima,
                Some(other) => {
                    return Err(InputError::field(
                        "method",
                        format!("must be \"akima\" or \"makima\", got \"{other}\""),
                    ));
                }
            }),
            "cardinal" => uniform(Basis::Cardinal {
                tension: tension?.unwrap_or(0.5),
            }),
            "catmull-rom" => uniform(Basis::CatmullRom),
            "bspline" => uniform(Basis::BSpline),
            "tensioned-bspline" => uniform(Basis::TensionedBSpline {
                tension: tension?.unwrap_or(1.0),
            }),
            // Either field given per joint: Barsky and Beatty's local bias and tension.
            "beta"
                if [&fields.bias, &fields.tension]
                    .iter()
                    .any(|v| matches!(v, Some(PerPoint::Each(_)))) =>
            {
                CurveKind::LocalBeta {
                    ends,
                    bias: fields.bias.clone().unwrap_or(PerPoint::All(1.0)),
                    tension: fields.tension.clone().unwrap_or(PerPoint::All(0.0)),
                }
            }
            "beta" => uniform(Basis::Beta {
                bias: bias?.unwrap_or(1.0),
                tension: tension?.unwrap_or(0.0),
            }),
            "matrix" => uniform(Basis::Matrix(
                fields
                    .matrix
                    .ok_or_else(|| InputError::field("matrix", "is missing"))?,
            )),
            "bezier" => CurveKind::Bezier,
            "natural" => interpolating(EndCondition::Natural),
            "periodic" => interpolating(EndCondition::Periodic),
            "not-a-knot" => interpolating(EndCondition::NotAKnot),
            _ => interpolating(EndCondition::Clamped {
                start: required(fields.start_derivative.clone(), "start_derivative")?,
                end: required(fields.end_derivative.clone(), "end_derivative")?,
            }),
        })
    }
}

//! One curve's mesh planned on the host in f64, when it is pushed into a
//! [`GeometryJob`](super::GeometryJob): its geometry checked against the curve, the width
//! made one more coordinate of its spline, where its cross-sections lie (the sampling's
//! places, or a tolerance's, carried and checked round by round), the first frame's normal,
//! and the vertex and triangle counts a renderer sizes its buffers from.

use super::frames::{self, Vec3};
use super::mesh::{self, Section, Shape};
use super::stroke::StrokePlan;
use super::tolerance::{self, Carried, FrameSlack, Swept};
use super::{Cap, Geometry, dash, widen};
use crate::conventions::Ends;
use crate::curve::{Curve, CurveKind};
use crate::error::{InputError, Shown};
use crate::fit::interp::EndCondition;
use crate::job::Derivatives;
use crate::memory;
use crate::sampling::{SampleLoc, SamplePlan, Sampling};
use crate::segment::SegmentTable;

/// The most cross-sections one curve may have (the contract's 2^20).
pub const MAX_SECTIONS: usize = 1 << 20;

/// One curve's mesh, planned: its widened table (the width its last coordinate), where its
/// cross-sections lie, and what the counts were made from.
#[derive(Clone, Debug)]
pub(super) struct Planned {
    pub(super) table: SegmentTable,
    pub(super) geometry: Geometry,
    pub(super) sampling: Sampling,
    pub(super) body: Body,
    pub(super) vertices: u64,
    pub(super) triangles: u64,
}

/// How a planned mesh is made.
#[derive(Clone, Debug)]
pub(super) enum Body {
    /// A tube or ribbon swept along the curve's frames.
    Swept {
        /// Where the frames are carried: the cross-sections in order of t (a dashed curve's:
        /// the undashed curve's and every dash's).
        locs: Vec<SampleLoc>,
        /// The arc length to each cross-section (closed curves, whose frames are closed up).
        lengths: Option<Vec<f64>>,
        shape: Shape,
        n0: Vec3,
        /// A dashed curve's pieces, each the indices of its cross-sections in `locs`; `None`:
        /// the whole curve is one piece (closed when the curve is).
        dashes: Option<Vec<Vec<usize>>>,
    },
    /// A 2-D stroke: one piece, or one a dash, each planned as an open stroke of its own.
    Stroke(Vec<StrokePlan>),
}

/// Refuses a mesh whose vertices u32 indices cannot reach.
pub(super) fn check_mesh_size(vertices: u64) -> Result<(), InputError> {
    if vertices > u64::from(u32::MAX) {
        return Err(InputError::field(
            "sampling",
            format!("makes a mesh of {vertices} vertices, more than 2^32 - 1"),
        ));
    }
    Ok(())
}

/// The vertices and triangles of a tube or ribbon at `places` cross-sections, or of its
/// `dashes` (each a list of indices into the places).
fn mesh_counts(
    shape: Shape,
    places: usize,
    dashes: Option<&[Vec<usize>]>,
    closed: bool,
) -> (u64, u64) {
    match dashes {
        None => mesh::counts(shape, places as u64, closed),
        Some(dashes) => dashes.iter().fold((0, 0), |(v, f), dash| {
            let (dv, df) = mesh::counts(shape, dash.len() as u64, false);
            (v + dv, f + df)
        }),
    }
}

/// The bytes of a mesh made in f64: its positions, normals and t, and its triangles.
pub(super) fn mesh_bytes(vertices: u64, triangles: u64) -> u128 {
    u128::from(vertices) * 56 + u128::from(triangles) * 12
}

/// Refuses a curve whose mesh will have at least `vertices` and `triangles`, where that is
/// more than 2^32 − 1 vertices or more bytes than the process has (the memory read only for a
/// mesh of a GiB or more; the job checks its whole once planned).
fn check_least_mesh(vertices: u64, triangles: u64) -> Result<(), InputError> {
    let bytes = mesh_bytes(vertices, triangles);
    let available = (bytes >= 1 << 30).then(memory::available_memory).flatten();
    let beyond = if vertices > u64::from(u32::MAX) {
        "more than 2^32 - 1 vertices".to_string()
    } else if let Some(available) = available.filter(|&a| bytes > u128::from(a)) {
        format!("more than the {available} bytes of memory the process has available")
    } else {
        return Ok(());
    };
    Err(InputError::field(
        "sampling",
        format!(
            "makes a mesh of at least {vertices} vertices and {triangles} triangles, {bytes} \
             bytes: {beyond}"
        ),
    ))
}

/// Whether the curve closes on itself (its frames are then closed up and its mesh wraps).
fn is_closed(kind: &CurveKind) -> bool {
    match kind {
        CurveKind::Uniform { ends, .. }
        | CurveKind::LocalBeta { ends, .. }
        | CurveKind::KochanekBartels { ends, .. } => *ends == Ends::Closed,
        CurveKind::Interpolating { condition, .. } => *condition == EndCondition::Periodic,
        _ => false,
    }
}

/// `curve`'s mesh for `geometry` at `sampling`, planned (see the module docs).
pub(super) fn plan(
    curve: &Curve,
    geometry: &Geometry,
    sampling: &Sampling,
) -> Result<Planned, InputError> {
    let dim = curve.points().dim();
    let wanted = if matches!(geometry, Geometry::Stroke(_)) {
        2
    } else {
        3
    };
    if dim != wanted {
        return Err(InputError::field(
            "geometry",
            format!(
                "a {} needs {wanted}-D points, got {dim} coordinates per point",
                geometry.name()
            ),
        ));
    }
    if let Sampling::At(_) = sampling {
        return Err(InputError::field(
            "sampling",
            "\"at\" places no cross-sections: geometry takes per_segment, arc_length or tolerance",
        ));
    }
    let tolerance = match *sampling {
        Sampling::Tolerance(tol) if !(tol.is_finite() && tol > 0.0) => {
            return Err(InputError::field(
                "tolerance",
                format!("must be a finite number > 0, got {}", Shown(tol)),
            ));
        }
        Sampling::Tolerance(tol) => Some(tol),
        _ => None,
    };
    let (width, field) = geometry.width();
    let table = widen::widened(curve, width, field)?.fit();
    table.check_range(Derivatives::Second)?;
    let shape = match geometry {
        Geometry::Stroke(_) => None,
        Geometry::Tube(tube) => {
            let sides = tube_sides(tube.sides, &table, tolerance)?;
            Some(Shape::Tube {
                sides,
                caps: tube.caps,
            })
        }
        Geometry::Ribbon(_) => Some(Shape::Ribbon),
    };
    // The places are the position's: its arc length, not the widened curve's.
    let position = curve.fit();
    let closed = is_closed(curve.kind());
    // The arc length, where dashes are laid by it or a closed tube's frames closed up within
    // a tolerance (whose placement needs the curve's length first); a per_segment or
    // arc_length closed tube measures the lengths to its places alone (`dash::lengths_to`).
    let map = (geometry.dash().is_some() || (closed && shape.is_some() && tolerance.is_some()))
        .then(|| dash::ArcMap::new(&position));
    let mut locs = match tolerance {
        None => {
            let plan = SamplePlan::new(&position, sampling)?;
            if plan.len() > MAX_SECTIONS {
                return Err(InputError::field(
                    "sampling",
                    format!("places {} cross-sections, more than 2^20", plan.len()),
                ));
            }
            (0..plan.len()).map(|i| plan.loc(i)).collect()
        }
        Some(tol) => {
            let swept = swept_kind(shape);
            let closing = map.as_ref().filter(|_| closed).map(dash::ArcMap::length);
            tolerance::places(
                &table,
                tol,
                swept,
                |bounds, h| {
                    let slack = FrameSlack {
                        closed_length: closing,
                    };
                    slack.a_priori(bounds, h)
                },
                MAX_SECTIONS,
            )?
        }
    };
    let pattern = match (geometry.dash(), &map) {
        (Some(pattern), Some(map)) => {
            pattern.check()?;
            let mut intervals = pattern.intervals(map.length())?;
            // A dash of length 0 makes a stroke's cap shapes and nothing else.
            let flat_caps = matches!(geometry, Geometry::Stroke(s) if s.cap != Cap::Butt);
            if !flat_caps {
                intervals.retain(|(a, b)| b > a);
            }
            Some((map, intervals))
        }
        _ => None,
    };
    let lay = |locs: &[SampleLoc]| -> Result<Option<Vec<Vec<SampleLoc>>>, InputError> {
        let Some((map, intervals)) = &pattern else {
            return Ok(None);
        };
        let pieces = dash::places(map, intervals, locs, sampling);
        let sections: usize = pieces.iter().map(Vec::len).sum();
        if sections + locs.len() > MAX_SECTIONS {
            return Err(InputError::field(
                "dash",
                format!("places {sections} cross-sections in its dashes, more than 2^20"),
            ));
        }
        Ok(Some(pieces))
    };
    let mut pieces = lay(&locs)?;
    let Some(shape) = shape else {
        let Geometry::Stroke(style) = geometry else {
            unreachable!("a shape for every swept geometry")
        };
        let strokes = match &pieces {
            None => vec![StrokePlan::new(&table, &locs, style, closed, tolerance)?],
            Some(pieces) => pieces
                .iter()
                .map(|piece| StrokePlan::new(&table, piece, style, false, tolerance))
                .collect::<Result<_, _>>()?,
        };
        let vertices = strokes.iter().map(|s| s.vertices).sum();
        let triangles = strokes.iter().map(|s| s.triangles).sum();
        return Ok(Planned {
            vertices,
            triangles,
            geometry: geometry.clone(),
            sampling: sampling.clone(),
            table,
            body: Body::Stroke(strokes),
        });
    };
    let first = section(&table, locs[0]);
    let t0 = frames::unit_tangent(first.d1, first.d2, false).unwrap_or_else(|| {
        // No direction at the start: the first cross-section that has one lends it.
        let (d1, d2): (Vec<Vec3>, Vec<Vec3>) = locs
            .iter()
            .map(|&l| {
                let s = section(&table, l);
                (s.d1, s.d2)
            })
            .unzip();
        frames::tangents(&d1, &d2)[0]
    });
    let n0 = frames::first_normal(t0, geometry.up())?;
    // Tolerance: the frames' own error is known once they are carried through every place
    // (the dashes' too); cells that fail are halved and the places laid again.
    let (locs, dashes, lengths) = loop {
        let (merged, indices) = match pieces.clone() {
            None => (locs.clone(), None),
            Some(pieces) => {
                let (merged, indices) = merge_by_t(locs.clone(), pieces);
                (merged, Some(indices))
            }
        };
        // The arc length to each cross-section of a closed curve, whose frames are closed up.
        let lengths: Option<Vec<f64>> = closed.then(|| match &map {
            Some(map) => merged.iter().map(|&loc| map.length_to(loc)).collect(),
            None => dash::lengths_to(&position, &merged),
        });
        let Some(tol) = tolerance else {
            break (merged, indices, lengths);
        };
        // Places are only ever added: the mesh they give now is the least the tolerance can
        // end with, refused before its cells are measured (a tube's cells, quad by quad, cost
        // as much as making the mesh).
        let (vertices, triangles) = mesh_counts(shape, merged.len(), indices.as_deref(), closed);
        check_least_mesh(vertices, triangles)?;
        let carried = Carried::of(&table, &merged, n0, lengths.as_deref());
        let slack = FrameSlack {
            closed_length: lengths.as_ref().and_then(|l| l.last().copied()),
        };
        let swept = swept_kind(Some(shape));
        let failing = carried.failing_cells(indices.as_deref(), swept, tol, slack)?;
        if failing.is_empty() {
            break (merged, indices, lengths);
        }
        let (before, first_failing) = (locs.len(), failing[0].t);
        locs.extend(failing);
        locs.sort_by(|a, b| a.t.total_cmp(&b.t));
        locs.dedup_by(|a, b| a.t == b.t && a.segment == b.segment);
        if locs.len() == before {
            // Cells too small to halve in f64, and still failing.
            return Err(InputError::field(
                "tolerance",
                format!(
                    "cannot be certified near t = {first_failing}: its cells cannot be halved \
                     further (use per_segment or arc_length sampling)"
                ),
            ));
        }
        if locs.len() > MAX_SECTIONS {
            return Err(InputError::field(
                "sampling",
                format!("tolerance places more than {MAX_SECTIONS} cross-sections"),
            ));
        }
        pieces = lay(&locs)?;
    };
    let (vertices, triangles) = mesh_counts(shape, locs.len(), dashes.as_deref(), closed);
    Ok(Planned {
        table,
        geometry: geometry.clone(),
        sampling: sampling.clone(),
        body: Body::Swept {
            locs,
            lengths,
            shape,
            n0,
            dashes,
        },
        vertices,
        triangles,
    })
}

/// A tube's sides: as given, or 8, or with tolerance the method's choice; given sides whose
/// polygon alone strays more than tol from the largest radius's circle are refused.
fn tube_sides(
    sides: Option<u32>,
    table: &SegmentTable,
    tolerance: Option<f64>,
) -> Result<u32, InputError> {
    if let Some(sides) = sides.filter(|&s| s < 3) {
        return Err(InputError::field(
            "sides",
            format!("a tube needs at least 3 sides, got {sides}"),
        ));
    }
    let Some(tol) = tolerance else {
        return Ok(sides.unwrap_or(8));
    };
    let Some(sides) = sides else {
        let radius = tolerance::largest_width(table);
        let sides = tolerance::default_sides(radius, tol);
        if sides as usize > MAX_SECTIONS {
            return Err(InputError::field(
                "tolerance",
                format!(
                    "{} asks more than 2^20 sides of a tube of radius up to {} (its polygon \
                     alone must stay within tol/2 of the circle)",
                    Shown(tol),
                    Shown(radius)
                ),
            ));
        }
        return Ok(sides);
    };
    // The largest radius met on a grid of each segment (the refusal must not rest on a bound).
    let dim = table.dim();
    let mut p = vec![0.0; dim];
    let mut largest = 0.0f64;
    for s in 0..table.len() {
        for i in 0..=32 {
            table.segment(s).eval(f64::from(i) / 32.0, &mut p);
            largest = largest.max(p[dim - 1]);
        }
    }
    let sagitta = largest * (1.0 - (std::f64::consts::PI / f64::from(sides)).cos());
    if sagitta > tol {
        return Err(InputError::field(
            "sides",
            format!(
                "{sides} sides stray {} from the circle of radius {largest}, more than the \
                 tolerance {tol}",
                Shown(sagitta)
            ),
        ));
    }
    Ok(sides)
}

/// What the tolerance bound is measured for.
fn swept_kind(shape: Option<Shape>) -> Swept {
    match shape {
        None => Swept::Stroke,
        Some(Shape::Tube { sides, .. }) => Swept::tube(sides),
        Some(Shape::Ribbon) => Swept::Ribbon,
    }
}

/// The undashed curve's places and every dash's, in one list in order of t (the frames are
/// carried through all of them), and each dash's places as indices into it.
fn merge_by_t(
    undashed: Vec<SampleLoc>,
    pieces: Vec<Vec<SampleLoc>>,
) -> (Vec<SampleLoc>, Vec<Vec<usize>>) {
    let mut tagged: Vec<(SampleLoc, Option<(usize, usize)>)> =
        undashed.into_iter().map(|loc| (loc, None)).collect();
    for (d, piece) in pieces.iter().enumerate() {
        tagged.extend(
            piece
                .iter()
                .enumerate()
                .map(|(i, &loc)| (loc, Some((d, i)))),
        );
    }
    // Stable: at equal t the undashed place comes first, a dash's in their own order.
    tagged.sort_by(|a, b| a.0.t.total_cmp(&b.0.t));
    let mut indices: Vec<Vec<usize>> = pieces.iter().map(|p| vec![0; p.len()]).collect();
    for (k, (_, tag)) in tagged.iter().enumerate() {
        if let Some((d, i)) = tag {
            indices[*d][*i] = k;
        }
    }
    (tagged.into_iter().map(|(loc, _)| loc).collect(), indices)
}

/// The widened table at one place: position, derivatives and width (its frame not yet set).
#[inline]
pub(super) fn section(table: &SegmentTable, loc: SampleLoc) -> Section {
    let segment = table.segment(loc.segment);
    let (mut p, mut d1, mut d2) = ([0.0; 4], [0.0; 4], [0.0; 4]);
    segment.jet(loc.u, &mut p, &mut d1, &mut d2);
    let clamped = p[3] < 0.0;
    Section {
        t: loc.t,
        position: [p[0], p[1], p[2]],
        d1: [d1[0], d1[1], d1[2]],
        d2: [d2[0], d2[1], d2[2]],
        width: p[3].max(0.0),
        width_d1: if clamped { 0.0 } else { d1[3] },
        tangent: [0.0; 3],
        normal: [0.0; 3],
    }
}

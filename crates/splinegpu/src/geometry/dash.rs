//! Dashes: a pattern of on and off lengths laid along the curve by arc length, each on
//! interval made as an open piece of its own (caps at both its ends, no join across a gap).
//!
//! With the pattern's lengths l_0, l_1, ... (on, off, on, ...), its period P = Σ l_i and the
//! offset d (how far into the pattern the curve's start lies), the pattern at arc length s
//! stands at (s + d) mod P, so the on intervals are [kP + a_i - d', kP + b_i - d'] for every
//! integer k, with [a_i, b_i] the pattern's i-th on interval and d' = d mod P in [0, P);
//! each is clipped to [0, L]. A closed curve's pattern starts at its first point and does
//! not wrap. An interval clipped to a point (touching 0 or L from outside) is dropped; one
//! of length 0 in the pattern itself is kept (a dotted line of round caps).
//!
//! A dash's cross-sections: per_segment, the undashed curve's places strictly inside it and
//! its two ends (an end on a joint taken on the segment that arrives there, so that a piece
//! ends with its own tangent; a dot's two ends are one place, on a joint the leaving side's); arc_length m, ceil((m - 1)(s_b - s_a) / L) + 1 places (at least 2) evenly
//! spaced by arc length from s_a to s_b.

use super::MAX_SECTIONS;
use crate::error::{InputError, Shown};
use crate::sampling::arc_length::{ArcTable, Cuts, DEFAULT_ARCLEN_ACCURACY, Speed};
use crate::sampling::{SampleLoc, Sampling};
use crate::segment::SegmentTable;

/// A dash pattern: alternately on and off lengths along the curve, in arc length.
#[derive(Clone, Debug, PartialEq)]
pub struct Dash {
    /// An even number of lengths >= 0 (on, off, on, off, ...) with a sum > 0.
    pub lengths: Vec<f64>,
    /// How far into the pattern the curve's start lies (any finite number).
    pub offset: f64,
}

impl Dash {
    /// Checks the pattern's rules.
    ///
    /// # Errors
    /// An odd count, a length that is negative or not finite, a sum of 0 ("dash"); an offset
    /// that is not finite ("dash_offset").
    pub(crate) fn check(&self) -> Result<(), InputError> {
        let n = self.lengths.len();
        if n == 0 || n % 2 == 1 {
            return Err(InputError::field(
                "dash",
                format!("must hold an even number of lengths (on, off, ...), got {n}"),
            ));
        }
        if let Some((i, x)) = self
            .lengths
            .iter()
            .enumerate()
            .find(|(_, x)| !(x.is_finite() && **x >= 0.0))
        {
            return Err(InputError::field(
                "dash",
                format!("lengths must be finite and >= 0: dash[{i}] = {}", Shown(*x)),
            ));
        }
        let period: f64 = self.lengths.iter().sum();
        if !(period > 0.0 && period.is_finite()) {
            return Err(InputError::field(
                "dash",
                format!("lengths must have a finite sum > 0, got {}", Shown(period)),
            ));
        }
        if !self.offset.is_finite() {
            return Err(InputError::field(
                "dash_offset",
                format!("must be a finite number, got {}", Shown(self.offset)),
            ));
        }
        Ok(())
    }

    /// The on intervals [s_a, s_b] of a curve of length `length`, in order (the module's
    /// docs).
    ///
    /// # Errors
    /// More intervals than a curve may have cross-sections ("dash").
    pub(crate) fn intervals(&self, length: f64) -> Result<Vec<(f64, f64)>, InputError> {
        let period: f64 = self.lengths.iter().sum();
        let ons = self.lengths.len() / 2;
        // Every period the curve meets holds at most `ons` intervals of 2 cross-sections each.
        let periods = (length / period).floor() + 2.0;
        if periods * ons as f64 * 2.0 > MAX_SECTIONS as f64 {
            return Err(InputError::field(
                "dash",
                format!(
                    "lays {} periods of {} along a curve of length {}: more than 2^20 \
                     cross-sections",
                    Shown(periods),
                    Shown(period),
                    Shown(length)
                ),
            ));
        }
        let shift = self.offset.rem_euclid(period);
        let mut pattern = Vec::with_capacity(ons);
        let mut at = 0.0;
        for pair in self.lengths.chunks_exact(2) {
            pattern.push((at, at + pair[0]));
            at += pair[0] + pair[1];
        }
        let mut intervals = Vec::new();
        for k in 0..periods as u64 {
            let start = k as f64 * period - shift;
            for &(a, b) in &pattern {
                let (a, b) = (start + a, start + b);
                let (ca, cb) = (a.max(0.0), b.min(length));
                if cb > ca || (a == b && (0.0..=length).contains(&a)) {
                    intervals.push((ca, cb));
                }
            }
        }
        Ok(intervals)
    }
}

/// A curve's arc length and its inverse: a length from the start to the place on the curve.
pub(crate) struct ArcMap<'a> {
    table: &'a SegmentTable,
    tables: Vec<ArcTable>,
    /// The length before each segment, and the whole length last.
    starts: Vec<f64>,
    accuracy: f64,
}

impl<'a> ArcMap<'a> {
    /// The map of the position table `table`, within [`DEFAULT_ARCLEN_ACCURACY`] of its length.
    pub(crate) fn new(table: &'a SegmentTable) -> Self {
        let tables = table.arc_tables(DEFAULT_ARCLEN_ACCURACY);
        let mut starts = Vec::with_capacity(tables.len() + 1);
        let mut sum = 0.0;
        for t in &tables {
            starts.push(sum);
            sum += t.length();
        }
        starts.push(sum);
        Self {
            table,
            tables,
            starts,
            accuracy: DEFAULT_ARCLEN_ACCURACY * sum,
        }
    }

    /// The curve's length.
    pub(crate) fn length(&self) -> f64 {
        self.starts[self.tables.len()]
    }

    /// The length from the start to `loc`.
    pub(crate) fn length_to(&self, loc: SampleLoc) -> f64 {
        self.starts[loc.segment] + self.tables[loc.segment].length_to(loc.u)
    }

    /// [`ArcMap::loc`] for the end of a piece: a place on a joint is taken on the segment
    /// that arrives there (at u = 1), whose tangent the piece ends with.
    pub(crate) fn loc_ending(&self, s: f64) -> SampleLoc {
        let loc = self.loc(s);
        if loc.u == 0.0 && loc.segment > 0 {
            return SampleLoc {
                segment: loc.segment - 1,
                u: 1.0,
                t: loc.t,
            };
        }
        loc
    }

    /// The place at length `s` from the start (clamped to the curve): the last segment that
    /// starts at or before it, and its u there (a place on a joint on the segment that leaves
    /// it).
    pub(crate) fn loc(&self, s: f64) -> SampleLoc {
        let segments = self.tables.len();
        if s >= self.length() {
            let last = self.table.segment(segments - 1);
            return SampleLoc {
                segment: segments - 1,
                u: 1.0,
                t: last.t0() + last.dt(),
            };
        }
        let segment = self.starts[..segments]
            .partition_point(|&start| start <= s)
            .saturating_sub(1);
        let u = self.tables[segment].inverse(s - self.starts[segment], self.accuracy);
        if u == 1.0 && segment + 1 < segments {
            // On the joint: the segment that leaves it, as a piece's start wants.
            let next = self.table.segment(segment + 1);
            return SampleLoc {
                segment: segment + 1,
                u: 0.0,
                t: next.t0(),
            };
        }
        let seg = self.table.segment(segment);
        SampleLoc {
            segment,
            u,
            t: seg.t0() + u * seg.dt(),
        }
    }
}

/// The arc length from the curve's start to each of `locs` (places of `table`'s curve, in order
/// of t), where no dash needs an [`ArcMap`] (a closed curve's closing-up): each step between
/// consecutive places measured by the 8-point Gauss–Legendre rule on the speed, cut at the
/// joints and where a segment's speed vanishes, on each side of which the speed is smooth
/// (per_segment 16, a step is a sixteenth of a segment: the rule's error is far below the
/// contract's 1e-4 L). A map's precise tables cost several times more, and its lengths are
/// needed only where dashes are laid.
pub(crate) fn lengths_to(table: &SegmentTable, locs: &[SampleLoc]) -> Vec<f64> {
    let mut lengths = Vec::with_capacity(locs.len());
    // The segment walked, its speed and the ends of its smooth parts, and the u reached.
    let mut walked: Option<(usize, Speed, Cuts)> = None;
    let (mut segment, mut u, mut total) = (0, 0.0, 0.0);
    let mut measure = |segment: usize, a: f64, b: f64| -> f64 {
        if b <= a {
            return 0.0;
        }
        let (speed, kinks) = match &walked {
            Some((s, speed, kinks)) if *s == segment => (speed, kinks),
            _ => {
                let speed = Speed::of(&table.segment(segment));
                let kinks = speed.kinks();
                let (_, speed, kinks) = walked.insert((segment, speed, kinks));
                (&*speed, &*kinks)
            }
        };
        let mut from = a;
        let mut length = 0.0;
        for &kink in kinks.iter().filter(|&&k| k > a && k < b) {
            length += speed.gl8(from, kink);
            from = kink;
        }
        length + speed.gl8(from, b)
    };
    for loc in locs {
        while segment < loc.segment {
            total += measure(segment, u, 1.0);
            (segment, u) = (segment + 1, 0.0);
        }
        total += measure(segment, u, loc.u);
        u = u.max(loc.u);
        lengths.push(total);
    }
    lengths
}

/// Each interval's cross-sections (the module's docs): `undashed` are the places the sampling
/// gives the whole curve.
pub(crate) fn places(
    map: &ArcMap<'_>,
    intervals: &[(f64, f64)],
    undashed: &[SampleLoc],
    sampling: &Sampling,
) -> Vec<Vec<SampleLoc>> {
    let length = map.length();
    intervals
        .iter()
        .map(|&(a, b)| {
            // A dot (a dash of length 0) takes one place, twice: on a joint, the leaving
            // segment's, so that its caps face one way.
            let start = map.loc(a);
            let end = if b > a { map.loc_ending(b) } else { start };
            match sampling {
                Sampling::ArcLength(m) => {
                    let steps = (f64::from(m - 1) * (b - a) / length).ceil().max(1.0) as usize;
                    let mut locs = Vec::with_capacity(steps + 1);
                    locs.push(start);
                    for i in 1..steps {
                        locs.push(map.loc(a + (b - a) * i as f64 / steps as f64));
                    }
                    locs.push(end);
                    locs
                }
                _ => {
                    // The undashed places are in order of t: those strictly inside, found by
                    // two binary searches rather than a pass over all of them per dash.
                    let from = undashed.partition_point(|l| l.t <= start.t);
                    let to = undashed.partition_point(|l| l.t < end.t).max(from);
                    let inside = undashed[from..to].iter().copied();
                    std::iter::once(start)
                        .chain(inside)
                        .chain(std::iter::once(end))
                        .collect()
                }
            }
        })
        .collect()
}

#[cfg(test)]
mod tests {
    use super::*;

    fn dash(lengths: &[f64], offset: f64) -> Dash {
        Dash {
            lengths: lengths.to_vec(),
            offset,
        }
    }

    #[test]
    fn intervals_follow_the_pattern_from_its_offset_clipped_to_the_curve() {
        // On 1, off 2 along 10: [0, 1], [3, 4], [6, 7], [9, 10].
        let got = dash(&[1.0, 2.0], 0.0).intervals(10.0).unwrap();
        assert_eq!(got, [(0.0, 1.0), (3.0, 4.0), (6.0, 7.0), (9.0, 10.0)]);
        // The start 0.5 into the pattern: its first dash is half gone.
        let got = dash(&[1.0, 2.0], 0.5).intervals(5.0).unwrap();
        assert_eq!(got, [(0.0, 0.5), (2.5, 3.5)]);
        // A negative offset is the same as its remainder: -2.5 = 0.5 - 3.
        assert_eq!(dash(&[1.0, 2.0], -2.5).intervals(5.0).unwrap(), got);
        // Starting inside a gap, and a dash ending exactly at the curve's start is dropped.
        let got = dash(&[1.0, 2.0], 1.0).intervals(4.0).unwrap();
        assert_eq!(got, [(2.0, 3.0)]);
        // Dots of length 0 are kept, also at the ends.
        let got = dash(&[0.0, 1.0], 0.0).intervals(2.0).unwrap();
        assert_eq!(got, [(0.0, 0.0), (1.0, 1.0), (2.0, 2.0)]);
        // Two dashes a period.
        let got = dash(&[1.0, 1.0, 2.0, 1.0], 0.0).intervals(6.0).unwrap();
        assert_eq!(got, [(0.0, 1.0), (2.0, 4.0), (5.0, 6.0)]);
    }

    #[test]
    fn bad_patterns_are_refused_by_name() {
        let message = |d: Dash| d.check().unwrap_err().to_string();
        assert!(message(dash(&[1.0], 0.0)).contains("even number of lengths"));
        assert!(message(dash(&[], 0.0)).contains("even number of lengths"));
        assert!(message(dash(&[1.0, -1.0], 0.0)).contains("dash[1] = -1"));
        assert!(message(dash(&[0.0, 0.0], 0.0)).contains("sum > 0"));
        assert!(message(dash(&[f64::MAX, f64::MAX], 0.0)).contains("finite sum"));
        assert!(message(dash(&[1.0, 1.0], f64::NAN)).starts_with("\"dash_offset\""));
        let error = dash(&[1e-9, 1e-9], 0.0).intervals(1.0).unwrap_err();
        assert_eq!(error.field.as_deref(), Some("dash"));
    }
    /// The lengths to places without a map agree with the map's precise lengths: on a cusp
    /// (the speed zero inside a segment, between two places), on a closed loop of several
    /// segments and at places on the joints (both sides' places of one joint included).
    #[test]
    fn lengths_to_places_agree_with_the_precise_map() {
        use crate::{Basis, Curve, CurveKind, Ends, Points};
        let bezier = |coords: Vec<f64>| {
            let kind = CurveKind::Uniform {
                basis: Basis::Matrix(crate::basis::bezier_rows()),
                ends: Ends::Control,
            };
            Curve::new(kind, Points::new(2, coords).unwrap())
                .unwrap()
                .fit()
        };
        let loop_points: Vec<f64> = (0..7)
            .flat_map(|i| {
                let a = std::f64::consts::TAU * f64::from(i) / 7.0;
                [(1.0 + 0.3 * (3.0 * a).sin()) * a.cos(), a.sin()]
            })
            .collect();
        let closed = CurveKind::Uniform {
            basis: Basis::CatmullRom,
            ends: Ends::Closed,
        };
        let tables = [
            bezier(vec![0.0, 0.0, 1.0, 1.0, 0.0, 1.0, 1.0, 0.0]),
            Curve::new(closed, Points::new(2, loop_points).unwrap())
                .unwrap()
                .fit(),
        ];
        for table in &tables {
            let map = ArcMap::new(table);
            let mut locs = Vec::new();
            for segment in 0..table.len() {
                let t0 = table.segment(segment).t0();
                let dt = table.segment(segment).dt();
                for k in 0..=13 {
                    let u = f64::from(k) / 13.0;
                    locs.push(SampleLoc {
                        segment,
                        u,
                        t: t0 + u * dt,
                    });
                }
            }
            let got = lengths_to(table, &locs);
            let length = map.length();
            for (loc, got) in locs.iter().zip(got) {
                let want = map.length_to(*loc);
                assert!(
                    (got - want).abs() <= 1e-9 * length,
                    "segment {} u {}: {got} against {want}",
                    loc.segment,
                    loc.u
                );
            }
        }
    }
}

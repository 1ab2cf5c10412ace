//! Dashes against their exact shapes: a dashed straight tube's pieces where the pattern puts
//! them along the length, each closed by its caps; a dashed trefoil's rings where the undashed
//! tube's are (the frames carried through the dashes, not restarted at each); dashed strokes
//! with round caps and joins covering exactly the points within w/2 of the path's on pieces
//! (joins inside a dash, none across a gap), and dotted lines of round or square dots.

use super::*;
use splinegpu::geometry::Dash;

fn dash(lengths: &[f64], offset: f64) -> Option<Dash> {
    Some(Dash {
        lengths: lengths.to_vec(),
        offset,
    })
}

/// The ranges of vertices of a mesh made of `pieces` capped tubes of `rings` rings each.
fn capped_tube_pieces(rings: &[usize], sides: usize) -> Vec<std::ops::Range<usize>> {
    let mut start = 0;
    rings
        .iter()
        .map(|r| {
            let end = start + r * sides + 2;
            let range = start..end;
            start = end;
            range
        })
        .collect()
}

/// The z axis from 0 to 4 (its length is t): on 1, off 1 gives [0, 1] and [2, 3] (the dash
/// of length 0 at 4 gives a tube nothing), each a capped tube whose rings are where the
/// sampling puts them, at the radius, and closed (every edge in two triangles of its piece).
#[test]
fn a_dashed_straight_tube_is_capped_pieces_where_the_pattern_puts_them() {
    let cases = [
        // per_segment 2: the undashed places inside each dash and its ends.
        (
            Sampling::PerSegment(2),
            0.0,
            vec![vec![0.0, 0.5, 1.0], vec![2.0, 2.5, 3.0]],
        ),
        // arc_length 9 (places 0.5 apart), 0.5 into the pattern: [0, 0.5], [1.5, 2.5],
        // [3.5, 4], with ceil(8 (s_b - s_a) / 4) + 1 places each.
        (
            Sampling::ArcLength(9),
            0.5,
            vec![vec![0.0, 0.5], vec![1.5, 2.0, 2.5], vec![3.5, 4.0]],
        ),
    ];
    for (sampling, offset, want) in cases {
        let tube = Geometry::Tube(Tube {
            radius: Width::Constant(0.25),
            sides: Some(8),
            caps: true,
            up: None,
            dash: dash(&[1.0, 1.0], offset),
        });
        let (job, m) = meshes(&axis(), &tube, &sampling);
        let rings: Vec<usize> = want.iter().map(Vec::len).collect();
        let pieces = capped_tube_pieces(&rings, 8);
        assert_eq!(job.vertex_count() as usize, pieces.last().unwrap().end);
        let triangles: usize = rings.iter().map(|r| 2 * (r - 1) * 8 + 16).sum();
        assert_eq!(job.triangle_count() as usize, triangles);
        for (piece, places) in pieces.iter().zip(&want) {
            for (j, &t) in places.iter().enumerate() {
                for k in 0..8 {
                    let v = piece.start + 8 * j + k;
                    assert!(
                        (m.t[v] - t).abs() < 1e-9,
                        "{sampling:?}: ring at {}",
                        m.t[v]
                    );
                    let p = vertex(&m, v);
                    assert!((p[2] - t).abs() < 1e-9);
                    assert!((p[0].hypot(p[1]) - 0.25).abs() < 1e-12);
                }
            }
            // The piece is closed by its caps, and no triangle joins it to another.
            let mut uses: HashMap<(u32, u32), usize> = HashMap::new();
            for &[a, b, c] in &m.triangles {
                if !piece.contains(&(a as usize)) {
                    continue;
                }
                for (p, q) in [(a, b), (b, c), (c, a)] {
                    assert!(piece.contains(&(p as usize)) && piece.contains(&(q as usize)));
                    *uses.entry((p.min(q), p.max(q))).or_insert(0) += 1;
                }
            }
            assert!(
                uses.values().all(|&n| n == 2),
                "{sampling:?}: a piece is not closed"
            );
        }
    }
}

/// A dash does not restart the frame: the dashed trefoil's rings lie where the undashed
/// tube's rings at the same t lie (the frames carried through both sets of places, and closed
/// up over the whole loop, differ from the undashed ones by the scheme's step error only),
/// where a frame started afresh at each dash would turn its rings by up to half a turn.
#[test]
fn a_dashed_closed_tube_takes_the_frames_carried_around_the_whole_loop() {
    let sampling = Sampling::PerSegment(16);
    let tube = |dash| {
        Geometry::Tube(Tube {
            radius: Width::Constant(0.1),
            sides: Some(6),
            caps: false,
            up: None,
            dash,
        })
    };
    let (_, whole) = meshes(&trefoil(), &tube(None), &sampling);
    let (_, dashed) = meshes(&trefoil(), &tube(dash(&[2.0, 1.3], 0.4)), &sampling);
    let mut matched = 0;
    let mut worst: f64 = 0.0;
    for v in 0..dashed.t.len() {
        // Rings of 6 from the start of each piece: the whole tube's vertex k of its ring at
        // the same t.
        let Some(w) = (0..whole.t.len()).find(|&w| whole.t[w] == dashed.t[v] && w % 6 == v % 6)
        else {
            continue;
        };
        let d = sub(vertex(&dashed, v), vertex(&whole, w));
        worst = worst.max(dot(d, d).sqrt());
        matched += 1;
    }
    assert!(matched > 6 * 100, "{matched} vertices at shared places");
    // Measured: 5.2e-10, the double reflection's step error.
    assert!(worst < 1e-6 * 0.1, "rings moved by {worst}");
}

/// The path's on pieces for arc lengths [a, b]: the polyline from a to b along `corners` (a
/// single point when a = b).
fn sub_polyline(corners: &[[f64; 2]], a: f64, b: f64) -> Vec<[f64; 2]> {
    let at = |s: f64| {
        let mut left = s;
        for w in corners.windows(2) {
            let length = (w[1][0] - w[0][0]).hypot(w[1][1] - w[0][1]);
            if left <= length {
                let f = left / length;
                return [
                    w[0][0] + f * (w[1][0] - w[0][0]),
                    w[0][1] + f * (w[1][1] - w[0][1]),
                ];
            }
            left -= length;
        }
        corners[corners.len() - 1]
    };
    let mut out = vec![at(a)];
    let mut start = 0.0;
    for w in corners.windows(2) {
        start += (w[1][0] - w[0][0]).hypot(w[1][1] - w[0][1]);
        if start > a && start < b {
            out.push(w[1]);
        }
    }
    out.push(at(b));
    out
}

fn distance_to_piece(p: [f64; 2], piece: &[[f64; 2]]) -> f64 {
    piece
        .windows(2)
        .map(|w| {
            let (dx, dy) = (w[1][0] - w[0][0], w[1][1] - w[0][1]);
            let squared = dx * dx + dy * dy;
            let s = if squared > 0.0 {
                (((p[0] - w[0][0]) * dx + (p[1] - w[0][1]) * dy) / squared).clamp(0.0, 1.0)
            } else {
                0.0
            };
            (p[0] - w[0][0] - s * dx).hypot(p[1] - w[0][1] - s * dy)
        })
        .fold(f64::INFINITY, f64::min)
}

fn dashed_stroke(cap: Cap, pattern: &[f64], offset: f64) -> Geometry {
    Geometry::Stroke(Stroke {
        width: Width::Constant(0.5),
        cap,
        join: Join::Round,
        miter_limit: 4.0,
        sides: 16,
        dash: dash(pattern, offset),
    })
}

/// The zigzag's length: 2 + 2 + 1.5 √2.
fn zigzag_length() -> f64 {
    4.0 + 1.5 * std::f64::consts::SQRT_2
}

/// Round caps and joins: the exact area is every point within w/2 of the on pieces. On 1.5,
/// off 0.7 from 0.3 into the pattern puts both corners inside dashes (their joins drawn);
/// on 1.5, off 1 puts the first corner in a gap (no join there: its disc would leave the
/// area) and a dash's end on the second corner (its cap faces the way the dash arrived).
#[test]
fn dashed_round_strokes_cover_the_points_within_half_the_width_of_the_on_pieces() {
    let h = 0.25;
    let sagitta = h * (1.0 - (std::f64::consts::PI / 8.0).cos());
    let length = zigzag_length();
    for (pattern, offset, dashes) in [
        ([1.5, 0.7], 0.3, vec![(0.0, 1.2), (1.9, 3.4), (4.1, 5.6)]),
        ([1.5, 1.0], 0.0, vec![(0.0, 1.5), (2.5, 4.0), (5.0, length)]),
    ] {
        let pieces: Vec<Vec<[f64; 2]>> = dashes
            .iter()
            .map(|&(a, b)| sub_polyline(&ZIGZAG, a, b))
            .collect();
        let distance = |p: [f64; 2]| {
            pieces
                .iter()
                .map(|piece| distance_to_piece(p, piece))
                .fold(f64::INFINITY, f64::min)
        };
        for sampling in [Sampling::PerSegment(4), Sampling::ArcLength(40)] {
            let (job, m) = meshes(
                &polyline(&ZIGZAG),
                &dashed_stroke(Cap::Round, &pattern, offset),
                &sampling,
            );
            assert_eq!(job.vertex_count() as usize, m.t.len());
            check(
                &m,
                |p| distance(p) <= h + 1e-9,
                |p| distance(p) < h - sagitta - 1e-9,
                [-0.5, -0.5],
                [4.0, 2.5],
            );
        }
    }
}

/// A pattern of on 0, off 1: round caps make a disc at every whole length along the path,
/// square caps a square of side w turned along the path there, butt caps nothing.
#[test]
fn dots_of_length_zero_are_their_caps() {
    let h = 0.25;
    let sagitta = h * (1.0 - (std::f64::consts::PI / 8.0).cos());
    let dots: Vec<[f64; 2]> = (0..=6)
        .map(|s| sub_polyline(&ZIGZAG, f64::from(s), f64::from(s))[0])
        .collect();
    let nearest = |p: [f64; 2]| {
        dots.iter()
            .map(|d| (p[0] - d[0]).hypot(p[1] - d[1]))
            .fold(f64::INFINITY, f64::min)
    };
    let (job, m) = meshes(
        &polyline(&ZIGZAG),
        &dashed_stroke(Cap::Round, &[0.0, 1.0], 0.0),
        &Sampling::PerSegment(4),
    );
    assert!(job.vertex_count() > 0);
    check(
        &m,
        |p| nearest(p) <= h + 1e-9,
        |p| nearest(p) < h - sagitta - 1e-9,
        [-0.5, -0.5],
        [4.0, 2.5],
    );
    // Square dots: within the square of half side h about each dot (turned with the path;
    // its circumscribed disc holds it, its inscribed disc is covered).
    let (_, m) = meshes(
        &polyline(&ZIGZAG),
        &dashed_stroke(Cap::Square, &[0.0, 1.0], 0.0),
        &Sampling::PerSegment(4),
    );
    check(
        &m,
        |p| nearest(p) <= h * std::f64::consts::SQRT_2 + 1e-9,
        |p| nearest(p) < h - 1e-9,
        [-0.5, -0.5],
        [4.0, 2.5],
    );
    let (job, _) = meshes(
        &polyline(&ZIGZAG),
        &dashed_stroke(Cap::Butt, &[0.0, 1.0], 0.0),
        &Sampling::PerSegment(4),
    );
    assert_eq!((job.vertex_count(), job.triangle_count()), (0, 0));
    // A pattern laid so finely that its dashes would pass 2^20 cross-sections is refused.
    let mut job = GeometryJob::new();
    let error = job
        .push(
            &polyline(&ZIGZAG),
            &dashed_stroke(Cap::Round, &[1e-6, 1e-6], 0.0),
            &Sampling::PerSegment(4),
        )
        .unwrap_err();
    assert_eq!(error.field.as_deref(), Some("dash"), "{error}");
}

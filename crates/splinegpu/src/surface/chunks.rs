//! A job's surfaces in chunks of bounded size, evaluated and written one chunk at a time (the
//! contract's "streamed", for surfaces): runs of whole surfaces, and a surface larger than a
//! chunk cut into pieces of it.
//!
//! A piece is a part of the surface's plan: a run of its vertices, in order, and a run of its
//! triangles, in order, whose indices number the whole surface's vertices (a triangle may name
//! vertices of other pieces). Written one after the other, the pieces are the surface's plan,
//! bit for bit. A per_segment net is cut by lines along u (a piece's vertices are whole lines,
//! its triangles the rows of cells starting on those lines) and made from its lines alone, so
//! its whole plan is never in memory; any other plan (a tolerance mesh, a welded patch list,
//! explicit (u, v)) is made once and its pieces copied out of it in turn.

use std::borrow::Cow;
use std::ops::Range;

use rayon::prelude::*;

use super::eval::{SurfaceSamples, evaluate_surfaces};
use super::job::SurfaceJob;
use super::mesh::{SurfacePlan, SurfaceSampling, grid_part};
use super::patch::PatchTable;
use crate::error::InputError;

/// One unit of [`SurfaceJob::chunks`]: whole surfaces, or one piece of a surface.
#[derive(Debug)]
pub struct SurfaceChunk {
    parts: Vec<ChunkPart>,
}

impl SurfaceChunk {
    /// The surfaces of `range`, whole.
    pub(crate) fn whole(range: Range<usize>) -> Self {
        Self {
            parts: range
                .map(|surface| ChunkPart {
                    surface,
                    first_vertex: 0,
                    last: true,
                    piece: None,
                })
                .collect(),
        }
    }

    /// What it holds, in order: one part per surface.
    #[must_use]
    pub fn parts(&self) -> &[ChunkPart] {
        &self.parts
    }
}

/// A surface in a [`SurfaceChunk`]: all of it, or a piece (see the module docs).
#[derive(Debug)]
pub struct ChunkPart {
    surface: usize,
    first_vertex: usize,
    last: bool,
    /// A piece's own plan; `None` for the whole surface (its plan is the job's).
    piece: Option<SurfacePlan>,
}

impl ChunkPart {
    /// The surface's index in the job.
    #[must_use]
    pub fn surface(&self) -> usize {
        self.surface
    }

    /// The surface's first vertex that this part holds (0 for the whole surface or its first
    /// piece): a sample's index in the surface is this plus its index in the part.
    #[must_use]
    pub fn first_vertex(&self) -> usize {
        self.first_vertex
    }

    /// Whether the part is the surface's first (the whole surface, or its first piece).
    #[must_use]
    pub fn is_first(&self) -> bool {
        self.first_vertex == 0
    }

    /// Whether the part ends the surface (the whole surface, or its last piece).
    #[must_use]
    pub fn is_last(&self) -> bool {
        self.last
    }
}

/// The iterator of [`SurfaceJob::chunks`].
#[derive(Debug)]
pub struct SurfaceChunks<'a> {
    job: &'a SurfaceJob,
    vertices: usize,
    /// The next surface not yet started.
    next: usize,
    /// The surface being cut into pieces.
    cut: Option<Cut<'a>>,
}

/// A surface being cut: which, how many pieces, the next, and where the pieces come from.
#[derive(Debug)]
struct Cut<'a> {
    surface: usize,
    pieces: usize,
    next: usize,
    source: Source<'a>,
}

/// Where a surface's pieces come from.
#[derive(Debug)]
enum Source<'a> {
    /// A per_segment net's grid, `lines` lines along u a piece.
    Grid {
        knots: [&'a [f64]; 2],
        closed: [bool; 2],
        ks: [Vec<usize>; 2],
        lines: usize,
    },
    /// A plan made whole, `vertices` of its vertices a piece.
    Plan {
        plan: Cow<'a, SurfacePlan>,
        vertices: usize,
    },
}

impl SurfaceJob {
    /// The job in chunks of at most `vertices` vertices (at least one line of a per_segment
    /// net's grid), in order, covering every surface: runs of whole surfaces, and each surface
    /// of more vertices cut into pieces (see the module docs). What a writer evaluates
    /// ([`SurfaceJob::try_evaluate_cpu_chunk`],
    /// [`GpuContext::evaluate_surface_chunk`](crate::GpuContext::evaluate_surface_chunk)) and
    /// writes one at a time, so that memory holds one chunk's samples however large a surface.
    #[must_use]
    pub fn chunks(&self, vertices: usize) -> SurfaceChunks<'_> {
        SurfaceChunks {
            job: self,
            vertices: vertices.max(1),
            next: 0,
            cut: None,
        }
    }

    /// A chunk's surfaces evaluated on the CPU in f64, a sample list per part (a piece's
    /// triangles index the whole surface's vertices), the memory allocated fallibly.
    ///
    /// # Errors
    /// The first part (by surface) whose samples could not be allocated, naming its sampling
    /// and vertex count.
    ///
    /// # Panics
    /// If the chunk is not of this job.
    pub fn try_evaluate_cpu_chunk(
        &self,
        chunk: &SurfaceChunk,
    ) -> Result<Vec<SurfaceSamples>, InputError> {
        // Surfaces on every thread (each also splits its vertices), a plan made again only
        // for its own surface's evaluation.
        chunk
            .parts
            .par_iter()
            .map(|part| {
                let (table, plan) = self.part_plan(part);
                evaluate_surfaces(table, &plan, self.derivatives(), self.normals()).map_err(|e| {
                    InputError::field(
                        "sampling",
                        format!(
                            "gives {} vertices, whose samples the process could not allocate \
                             ({e})",
                            plan.vertices.len()
                        ),
                    )
                    .in_surface(part.surface)
                })
            })
            .collect()
    }

    /// Each part's table and plan, for the GPU path.
    pub(crate) fn chunk_plans<'p>(
        &'p self,
        chunk: &'p SurfaceChunk,
    ) -> Vec<(&'p PatchTable, Cow<'p, SurfacePlan>)> {
        chunk
            .parts
            .iter()
            .map(|part| self.part_plan(part))
            .collect()
    }

    /// A part's table and plan: a piece's own, or the whole surface's (kept, or made again).
    fn part_plan<'p>(&'p self, part: &'p ChunkPart) -> (&'p PatchTable, Cow<'p, SurfacePlan>) {
        let surface = &self.surfaces()[part.surface];
        let plan = match &part.piece {
            Some(piece) => Cow::Borrowed(piece),
            None => surface.plan(),
        };
        (surface.table(), plan)
    }
}

impl Iterator for SurfaceChunks<'_> {
    type Item = SurfaceChunk;

    fn next(&mut self) -> Option<SurfaceChunk> {
        if let Some(cut) = &mut self.cut {
            let part = cut.piece();
            if part.last {
                self.cut = None;
                self.next += 1;
            }
            return Some(SurfaceChunk { parts: vec![part] });
        }
        let surfaces = self.job.surfaces();
        let first = surfaces.get(self.next)?;
        if first.vertices() > self.vertices {
            let mut cut = Cut::new(self.job, self.next, self.vertices);
            let part = cut.piece();
            if part.last {
                self.next += 1;
            } else {
                self.cut = Some(cut);
            }
            return Some(SurfaceChunk { parts: vec![part] });
        }
        let start = self.next;
        let mut held = 0;
        while let Some(s) = surfaces.get(self.next)
            && held + s.vertices() <= self.vertices
        {
            held += s.vertices();
            self.next += 1;
        }
        Some(SurfaceChunk::whole(start..self.next))
    }
}

impl<'a> Cut<'a> {
    /// Surface `s` of `job` to cut into pieces of at most `vertices` vertices (at least a line
    /// of a grid).
    fn new(job: &'a SurfaceJob, s: usize, vertices: usize) -> Self {
        let surface = &job.surfaces()[s];
        let table = surface.table();
        let source = match (surface.sampling(), table.knots()) {
            (SurfaceSampling::PerSegment(k), Some(knots)) => {
                let ks = [0, 1].map(|d| vec![k[d] as usize; knots[d].len() - 1]);
                let closed = table.closed();
                let cols = ks[1].iter().sum::<usize>() + usize::from(!closed[1]);
                Source::Grid {
                    knots,
                    closed,
                    ks,
                    lines: (vertices / cols).max(1),
                }
            }
            _ => Source::Plan {
                plan: surface.plan(),
                vertices,
            },
        };
        let pieces = match &source {
            Source::Grid {
                ks, closed, lines, ..
            } => {
                let rows = ks[0].iter().sum::<usize>() + usize::from(!closed[0]);
                rows.div_ceil(*lines)
            }
            Source::Plan { plan, vertices } => plan.vertices.len().div_ceil(*vertices),
        };
        Self {
            surface: s,
            pieces,
            next: 0,
            source,
        }
    }

    /// The next piece.
    fn piece(&mut self) -> ChunkPart {
        let (i, last) = (self.next, self.next + 1 == self.pieces);
        self.next += 1;
        let (first_vertex, plan) = match &self.source {
            Source::Grid {
                knots,
                closed,
                ks,
                lines,
            } => {
                let rows = ks[0].iter().sum::<usize>() + usize::from(!closed[0]);
                let cols = ks[1].iter().sum::<usize>() + usize::from(!closed[1]);
                let cells_u: usize = ks[0].iter().sum();
                let along = i * lines..((i + 1) * lines).min(rows);
                // The rows of cells starting on the piece's lines; the last piece takes the
                // rest (an open grid has a line more than rows of cells).
                let end = if last {
                    cells_u
                } else {
                    along.end.min(cells_u)
                };
                let cell_rows = along.start.min(cells_u)..end;
                let ks = [ks[0].as_slice(), ks[1].as_slice()];
                (
                    along.start * cols,
                    grid_part(*knots, *closed, ks, along, cell_rows),
                )
            }
            Source::Plan { plan, vertices } => {
                let n = plan.vertices.len();
                let run = i * vertices..((i + 1) * vertices).min(n);
                // Triangles in proportion: piece i takes [i T / pieces, (i + 1) T / pieces).
                let share = |i: usize, total: usize| {
                    (i as u128 * total as u128 / self.pieces as u128) as usize
                };
                let triangles = plan
                    .triangles
                    .as_ref()
                    .map(|t| t[share(i, t.len())..share(i + 1, t.len())].to_vec());
                (
                    run.start,
                    SurfacePlan {
                        vertices: plan.vertices[run].to_vec(),
                        triangles,
                        cells: Vec::new(),
                    },
                )
            }
        };
        ChunkPart {
            surface: self.surface,
            first_vertex,
            last,
            piece: Some(plan),
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::basis::Basis;
    use crate::curve::Ends;
    use crate::job::Derivatives;
    use crate::surface::{Net, Surface, SurfaceKind};

    /// A rows x cols net of 3-D points with some relief.
    fn net(rows: usize, cols: usize) -> Net {
        let coords = (0..rows * cols)
            .flat_map(|p| {
                let (i, j) = ((p / cols) as f64, (p % cols) as f64);
                [i, j, (i * 0.7).sin() * (j * 1.3).cos()]
            })
            .collect();
        Net::new(3, rows, cols, coords).unwrap()
    }

    fn job() -> SurfaceJob {
        let uniform = |ends| SurfaceKind::Uniform {
            basis: Basis::BSpline,
            ends: [ends; 2],
        };
        let table = |kind, net| Surface::new(kind, net).unwrap().fit();
        let patches = vec![std::array::from_fn(|k| k)];
        let mut job = SurfaceJob::new(Derivatives::First, true).keeping_plans_up_to(0);
        let surfaces = [
            (
                table(uniform(Ends::Closed), net(6, 5)),
                SurfaceSampling::PerSegment([3, 2]),
            ),
            (
                table(uniform(Ends::Repeat), net(5, 7)),
                SurfaceSampling::PerSegment([2, 3]),
            ),
            (
                table(SurfaceKind::Bezier, net(7, 7)),
                SurfaceSampling::Tolerance(0.02),
            ),
            (
                table(SurfaceKind::BezierPatches { patches }, net(16, 1)),
                SurfaceSampling::PerSegment([4, 4]),
            ),
            (
                table(SurfaceKind::Bezier, net(4, 4)),
                SurfaceSampling::At(vec![[0.5, 0.25], [1.0, 1.0], [0.0, 0.5]]),
            ),
        ];
        for (table, sampling) in surfaces {
            job.push(table, sampling).unwrap();
        }
        job
    }

    /// Whatever the chunk size, the parts come in order and, laid end to end, are each
    /// surface's whole samples bit for bit: vertices, values, patches and triangles (a piece's
    /// numbering the whole surface's vertices); no chunk holds more vertices than its size
    /// unless it is one line of a grid (at most 19 vertices here).
    #[test]
    fn pieces_laid_end_to_end_are_the_whole_samples() {
        let job = job();
        let whole = job.evaluate_cpu();
        for size in [1, 7, 40, 100, 1 << 20] {
            let mut joined: Vec<SurfaceSamples> = Vec::new();
            for chunk in job.chunks(size) {
                let samples = job.try_evaluate_cpu_chunk(&chunk).unwrap();
                let held: usize = samples.iter().map(SurfaceSamples::len).sum();
                assert!(held <= size.max(19), "size {size}: a chunk of {held}");
                for (part, s) in chunk.parts().iter().zip(samples) {
                    if part.is_first() {
                        assert_eq!(part.surface(), joined.len(), "size {size}");
                        joined.push(s);
                        continue;
                    }
                    assert_eq!(part.surface() + 1, joined.len(), "size {size}");
                    let last = joined.last_mut().unwrap();
                    assert_eq!(part.first_vertex(), last.len(), "size {size}");
                    last.uv.extend(s.uv);
                    last.points.extend(s.points);
                    for (to, from) in [(&mut last.du, s.du), (&mut last.dv, s.dv)] {
                        to.as_mut().unwrap().extend(from.unwrap());
                    }
                    last.normals.as_mut().unwrap().extend(s.normals.unwrap());
                    if let Some(p) = s.patch {
                        last.patch.as_mut().unwrap().extend(p);
                    }
                    if let Some(t) = s.triangles {
                        last.triangles.as_mut().unwrap().extend(t);
                    }
                }
            }
            assert_eq!(joined, whole, "size {size}");
        }
    }
}

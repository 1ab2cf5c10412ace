//! The library's GPU tests, in one binary whose harness (libtest-mimic) looks for an adapter
//! first: on a machine where wgpu finds none they are reported as ignored, not passed, and
//! under CI (`CI=true`) they run and fail, so that a broken driver install is never green.
//!
//! Each test compares the GPU with the f64 reference under the accuracy promise
//! ([`splinegpu::accuracy`]), curves and surfaces, or checks the renderer path; `cargo test --test gpu -- --list`
//! lists them.

#[path = "../it/arc_lengths.rs"]
mod arc_lengths;
mod geometric_sampling;
mod geometry;
mod gpu_vs_cpu;
mod render;
#[path = "../it/shapes.rs"]
mod shapes;
#[path = "../it/support.rs"]
mod support;
mod surfaces;

// The CPU tests' files whose cases the GPU is checked on too: their `#[test]`s are not built
// in this binary (no libtest), their cases are, and their `..._gpu_...` functions are trials.
#[path = "../it/hermite.rs"]
#[allow(
    dead_code,
    unused_imports,
    reason = "only the cases and the GPU trial are used here"
)]
mod hermite;
#[path = "../it/kochanek_bartels.rs"]
#[allow(
    dead_code,
    unused_imports,
    reason = "only the cases and the GPU trial are used here"
)]
mod kochanek_bartels;
#[path = "../it/local_beta.rs"]
#[allow(
    dead_code,
    unused_imports,
    reason = "only the cases and the GPU trial are used here"
)]
mod local_beta;
#[path = "../it/nurbs.rs"]
#[allow(
    dead_code,
    unused_imports,
    reason = "only the cases and the GPU trial are used here"
)]
mod nurbs;
#[path = "../it/geometric_sampling.rs"]
#[allow(
    dead_code,
    unused_imports,
    reason = "only the cases and the GPU trial are used here"
)]
mod sampling_cases;
#[path = "../it/scipy_fixture.rs"]
#[allow(
    dead_code,
    unused_imports,
    reason = "the fixtures' readers the cases use"
)]
mod scipy_fixture;
#[path = "../it/query/surface_checks.rs"]
mod surface_checks;

fn main() -> std::process::ExitCode {
    let tests = support::gpu_trials![
        gpu_vs_cpu::gpu_matches_cpu_for_every_family_end_and_dimension,
        gpu_vs_cpu::gpu_matches_cpu_near_one_million,
        gpu_vs_cpu::gpu_matches_cpu_on_2000_mixed_curves_in_one_call,
        gpu_vs_cpu::jobs_split_into_many_dispatches_give_the_same_samples,
        gpu_vs_cpu::values_into_a_callers_planes_equal_evaluates,
        #[cfg(feature = "profiling")]
        gpu_vs_cpu::timed_evaluations_give_what_untimed_ones_give,
        #[cfg(feature = "profiling")]
        gpu_vs_cpu::every_kernel_shape_meets_the_promise,
        gpu_vs_cpu::empty_sample_lists_give_empty_curves,
        gpu_vs_cpu::gpu_matches_cpu_on_10000_interpolating_curves_with_their_own_knots,
        gpu_vs_cpu::gpu_places_t_inside_a_segment_a_million_times_narrower_near_1e4,
        gpu_vs_cpu::positions_of_knots_closer_than_f32_reaches_are_evaluated,
        gpu_vs_cpu::eight_threads_on_one_context_each_get_what_they_get_alone,
        gpu_vs_cpu::evaluate_into_reuses_samples_across_jobs_of_other_shapes,
        gpu_vs_cpu::a_weighted_nurbs_circle_stays_on_the_circle_on_the_gpu,
        geometric_sampling::arc_length_samples_placed_by_the_gpu_are_evenly_spaced_within_3e_5_of_the_length,
        geometry::tubes_ribbons_and_strokes_of_many_kinds_in_one_call_keep_the_promise,
        geometry::a_renderer_records_meshes_into_its_own_buffers_and_refits_moving_curves,
        render::recorded_samples_follow_the_output_layout,
        render::unusable_target_buffers_are_errors,
        surfaces::gpu_surfaces_of_every_kind_in_one_call_keep_the_promise,
        surfaces::gpu_surfaces_without_derivatives_give_positions_only,
        surfaces::a_renderer_records_surfaces_into_its_own_buffers_and_refits_a_moving_net,
        surfaces::a_vertex_between_two_patches_is_the_later_patchs_on_the_gpu,
        hermite::the_hermite_kinds_meet_the_gpu_promise,
        kochanek_bartels::per_point_tcb_on_uneven_keys_meets_the_gpu_promise,
        local_beta::the_gpu_keeps_the_promise_on_local_bias_and_tension_near_the_origin_and_at_1e6,
        nurbs::scipys_bspline_cases_meet_the_gpu_promise,
        nurbs::basis_sums_meet_the_gpu_promise,
        sampling_cases::geometric_samplings_evaluate_on_the_gpu_within_the_promise,
        surfaces::closest_points_and_rays_on_the_gpu_are_the_certified_ones_within_the_bound,
    ];
    libtest_mimic::run(&libtest_mimic::Arguments::from_args(), tests).exit_code()
}

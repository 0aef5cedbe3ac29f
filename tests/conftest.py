import os
import tempfile
from pathlib import Path

import pytest

os.environ.setdefault("MPLBACKEND", "Agg")
# the launcher's reach maps are cached in a folder of this session, never in the user's cache
os.environ.setdefault("TENNISLAB_CACHE_DIR", tempfile.mkdtemp(prefix="tennislab-test-cache-"))


def _find_realdata() -> str:
    """``shared/realdata`` beside the checkout (or beside its parent, for a worktree); the first path when
    neither exists (the tests that read it then skip)."""
    root = Path(__file__).resolve().parents[1]
    for up in (root.parent, root.parent.parent):
        if (up / "shared" / "realdata").is_dir():
            return str(up / "shared" / "realdata")
    return str(root.parent / "shared" / "realdata")


#: The real data the tests read (``Path(os.environ["TENNISLAB_REALDATA"])``): set it to use another folder.
os.environ.setdefault("TENNISLAB_REALDATA", _find_realdata())


@pytest.fixture(autouse=True, scope="session")
def _clean_working_folder(tmp_path_factory):
    """Every test runs from an empty folder: a developer's ``./tennislab.toml`` cannot change the
    results (the CLI reads it from the working folder), and no test writes into the checkout."""
    old = os.getcwd()
    os.chdir(tmp_path_factory.mktemp("cwd"))
    yield
    os.chdir(old)


@pytest.fixture(scope="session")
def client():
    """One running web app (with its worker processes) shared by every test that talks to it."""
    pytest.importorskip("fastapi")
    pytest.importorskip("httpx")
    from fastapi.testclient import TestClient

    from tennislab.app.server import create_app

    with TestClient(create_app(allowed_hosts=["testserver"])) as c:
        yield c


# ------------------------------------------------------------------ the fast subset (`make check`)
#: Tests that ``make check`` (``pytest -m "not slow and not e2e"``) leaves out, marked ``slow`` here in one
#: place: whole files that start servers, browsers or processes, build databases or run every docs example,
#: and single tests (``file::function``, all parameters) that took more than ~1.2 s each on the shared
#: 2-core machine. ``make test`` runs them all; a test in ``test_repository.py`` checks every entry still
#: names a test. Mark a new long test ``@pytest.mark.slow`` in its file, or add it here.
SLOW_PATHS = (
    "tests/app/",
    "tests/e2e/",
    "tests/calibrate/test_realdata.py",
    "tests/cli/test_app.py",
    "tests/cli/test_fuzz_corpus.py",
    "tests/cli/test_launcher_db.py",
    "tests/launcher/test_db.py",
    "tests/report/test_report.py",
    "tests/test_docs.py::test_docs_example",
    "tests/test_docs.py::test_quoted_numbers",
    "tests/test_docs.py::test_generated_spans",
    "tests/test_frontends.py",
    "tests/batch/test_dask.py",
)
SLOW_TESTS = {
    "tests/batch/test_batch.py::test_fly_chunks_bit_identical_to_one_batch",
    "tests/batch/test_batch.py::test_resume_skips_finished_chunks",
    "tests/batch/test_store_recovery.py::test_any_damage_recovers_to_the_same_result",
    "tests/calibrate/test_serves_calibration.py::test_calibration_recovers_cd_and_cl_with_a_known_axis",
    "tests/calibrate/test_serves_calibration.py::test_calibration_recovers_cd_and_the_spin_axes",
    "tests/calibrate/test_tracks.py::test_drag_alone_without_spin",
    "tests/calibrate/test_tracks.py::test_recovers_cd_and_cl_with_known_spin",
    "tests/cli/test_calibrate.py::test_serves_writes_a_table_every_command_reads",
    "tests/cli/test_fly.py::test_every_accepted_figure_type_is_written",
    "tests/cli/test_fly.py::test_fly_bad_input_one_line_exit_2",
    "tests/cli/test_fly.py::test_fly_nan_velocity_subprocess",
    "tests/cli/test_fly.py::test_fly_physics_flags_and_plot",
    "tests/cli/test_fly.py::test_plots_are_written_with_the_users_umask",
    "tests/cli/test_fly.py::test_the_help_examples_run",
    "tests/cli/test_fly_bounces.py::test_plots_frame_every_bounce_and_the_apex",
    "tests/cli/test_fly_bounces.py::test_surface_changes_the_bounce",
    "tests/cli/test_launcher.py::test_aim_json_contract",
    "tests/cli/test_launcher.py::test_drill_cli",
    "tests/cli/test_launcher.py::test_material_rejects_flags_it_ignores",
    "tests/cli/test_serve.py::test_impact_json_contract",
    "tests/cli/test_serve.py::test_serve_3d_and_plot",
    "tests/cli/test_serve.py::test_serve_mc_contract",
    "tests/cli/test_serve.py::test_serve_mc_json_keys_and_resume",
    "tests/cli/test_serve.py::test_serve_mc_scheduler_flag",
    "tests/cli/test_serve.py::test_serve_window_all_players",
    "tests/cli/test_serve.py::test_serve_window_contract",
    "tests/core/test_domain.py::test_callable_model_used_by_batch_path",
    "tests/core/test_domain.py::test_inline_tag_survives_pickling_to_a_fresh_process",
    "tests/core/test_flight_accuracy.py::test_batch_landing_within_0p01_mm_of_reference",
    "tests/core/test_flight_accuracy.py::test_no_nan_anywhere_in_supported_range",
    "tests/core/test_flight_bounds.py::test_no_input_hangs_or_answers_nan",
    "tests/core/test_flight_bounds.py::test_whole_allowed_range_lands_finite_in_both_paths",
    "tests/core/test_flight_obstacle.py::test_obstacle_property_batch_equals_scipy",
    "tests/io/test_config.py::test_any_parsed_document_gives_data_or_one_input_error",
    "tests/io/test_courtvision.py::test_fuzz_serves_rows",
    "tests/io/test_courtvision.py::test_real_files",
    "tests/io/test_hawkeye.py::test_fuzz_json_structures",
    "tests/io/test_hawkeye.py::test_fuzz_mutated_points",
    "tests/io/test_track_cameras.py::test_fuzz_camera_json",
    "tests/io/test_track_cameras.py::test_fuzz_detections",
    "tests/io/test_track_cameras.py::test_fuzz_rows",
    "tests/launcher/test_aim.py::test_aim_property_never_breaks_tolerances_or_preferences",
    "tests/launcher/test_aim.py::test_preferences_are_met_or_refused_naming_the_parameter",
    "tests/linecall/test_linecall.py::test_cli_track_json_contract",
    "tests/linecall/test_linecall.py::test_uncertainty_is_calibrated",
    "tests/linecall/test_rally.py::test_calls_match_the_truth_with_events",
    "tests/linecall/test_rally.py::test_cli_rally_json_csv_plot",
    "tests/linecall/test_rally.py::test_hits_found_without_events_or_shot_records",
    "tests/linecall/test_rally.py::test_rows_frame_and_parallel_workers",
    "tests/linecall/test_robust.py::test_rejection_is_bounded",
    "tests/serve/test_mc.py::test_chunk_size_and_mapper_do_not_change_results",
    "tests/serve/test_mc.py::test_flat_serve_has_smaller_margin_than_topspin",
    "tests/serve/test_mc.py::test_p_success_agrees_with_an_independent_generator",
    "tests/serve/test_mc.py::test_processes_scheduler_is_bit_identical",
    "tests/serve/test_mc.py::test_reproducible_and_seeded",
    "tests/serve/test_mc.py::test_scatter_table_covers_every_draw_and_interpolates",
    "tests/serve/test_mc.py::test_statistics_equal_numpy_on_the_samples",
    "tests/serve/test_serve.py::test_default_model_within_the_passive_bound",
    "tests/serve/test_verdict.py::test_default_serve_is_robust",
    "tests/trajectory/test_flight.py::test_launch_vocabulary_round_trips",
    "tests/trajectory/test_flight.py::test_the_net_stops_the_ball_by_default",
}


def pytest_collection_modifyitems(config, items):
    for item in items:
        nodeid = item.nodeid.replace("\\", "/")
        if nodeid.startswith(SLOW_PATHS) or nodeid.split("[")[0] in SLOW_TESTS:
            item.add_marker(pytest.mark.slow)

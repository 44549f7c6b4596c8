"""Runs: the step callback, stopping, Ctrl-C and restarts, output=None, threads."""
import json
import os
import signal
import threading
import time

import numpy as np
import pytest

import fibrane
from conftest import coarse_peeling_text


def test_callback_sees_each_step_and_stops_the_run(peeling, tmp_path):
    seen = []

    def callback(t, step, monitors, state):
        seen.append((t, step, monitors["reaction_total_z"], state.displacements("fiber").shape, state.unknowns.shape))
        return step < 2

    result = fibrane.run(peeling, output=tmp_path / "out", callback=callback)
    assert result.outcome == "stopped" and result.steps == 2
    assert "step callback" in result.message and result.summary["outcome"] == "stopped"
    assert [s[1] for s in seen] == [1, 2]
    assert len(result.history["t"]) == 3  # the initial state and two steps
    for (t, step, reaction, shape, unknowns), row in zip(seen, range(1, 3)):
        assert t == result.history["t"][row] and reaction == result.history["reaction_total_z"][row]
        assert shape == result.displacements("fiber").shape and unknowns == result.unknowns().shape


def test_callback_exception_stops_the_run_and_is_raised(peeling, tmp_path):
    class Enough(Exception):
        pass

    def callback(t, step, monitors, state):
        if step == 1:
            raise Enough("enough")

    with pytest.raises(Enough):
        fibrane.run(peeling, output=tmp_path / "out", callback=callback)
    summary = json.loads((tmp_path / "out" / "summary.json").read_text())
    assert summary["outcome"] == "stopped" and summary["steps"] == 1


def test_step_state_expires_after_the_callback(peeling):
    kept = []
    fibrane.run(peeling, callback=lambda t, step, monitors, state: kept.append(state) or False)
    with pytest.raises(RuntimeError, match="returned"):
        kept[0].unknowns


def test_sigint_interrupts_like_the_cli_and_the_run_restarts(tmp_path):
    text = coarse_peeling_text(max_steps=5)
    whole = fibrane.run(fibrane.Case.from_yaml(text), output=tmp_path / "whole")

    def interrupt(t, step, monitors, state):
        if step == 2:
            os.kill(os.getpid(), signal.SIGINT)

    with pytest.raises(KeyboardInterrupt, match="interrupted"):
        fibrane.run(fibrane.Case.from_yaml(text), output=tmp_path / "cut", callback=interrupt)
    summary = json.loads((tmp_path / "cut" / "summary.json").read_text())
    assert summary["interrupted"] == "SIGINT" and summary["steps"] == 2
    restarted = fibrane.run(fibrane.Case.from_yaml(text), output=tmp_path / "cut", restart=True)
    assert restarted.steps == whole.steps and restarted.summary["restarted_from_step"] == 2
    for column, values in whole.history.items():
        np.testing.assert_allclose(restarted.history[column], values, rtol=1e-10, atol=1e-10, err_msg=column)


def test_temporary_output_comes_back_and_is_removed(peeling):
    result = fibrane.run(peeling, threads=1)
    directory = result.directory
    assert os.path.isfile(os.path.join(directory, "history.csv"))
    assert result.summary["steps"] == result.steps == len(result.history["t"]) - 1
    del result
    assert not os.path.exists(directory)


def test_run_arguments_are_checked(peeling, tmp_path):
    with pytest.raises(ValueError, match="restart"):
        fibrane.run(peeling, restart=True)
    with pytest.raises(ValueError, match="max_steps"):
        fibrane.run(peeling, max_steps=0)
    with pytest.raises(TypeError, match="callback"):
        fibrane.run(peeling, callback=3)
    result = fibrane.run(peeling, output=tmp_path / "short", max_steps=1)
    assert result.outcome == "max_steps" and result.steps == 1


def test_the_gil_is_released_while_the_run_computes(peeling):
    ticks, done = [], threading.Event()

    def count():
        while not done.is_set():
            ticks.append(time.perf_counter())
            time.sleep(0.002)

    counter = threading.Thread(target=count)
    counter.start()
    start = time.perf_counter()
    result = fibrane.run(peeling)
    end = time.perf_counter()
    done.set()
    counter.join()
    during = [t for t in ticks if start < t < end]
    # Another Python thread ran throughout the run: at least a tick per 20 ms of it.
    assert result.steps > 0 and len(during) > (end - start) / 0.02


def test_threads_zero_is_all_cores_after_another_count(peeling):
    fibrane.run(peeling, threads=1, max_steps=1)
    assert fibrane._core.max_threads() == 1
    fibrane.run(peeling, max_steps=1)
    expected = int(os.environ["OMP_NUM_THREADS"]) if "OMP_NUM_THREADS" in os.environ else os.cpu_count()
    assert fibrane._core.max_threads() == expected

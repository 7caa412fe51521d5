"""guardsim.envs: Gymnasium's and PettingZoo's checkers, seeding, determinism, and agreement with the planners."""

from __future__ import annotations

import importlib
import subprocess
import sys
import warnings
from collections.abc import Iterator
from contextlib import contextmanager
from typing import Any

import numpy as np
import pytest

gymnasium = pytest.importorskip("gymnasium")
pytest.importorskip("pettingzoo")

from gymnasium.utils.env_checker import check_env, data_equivalence  # noqa: E402
from pettingzoo.test import api_test, parallel_api_test, parallel_seed_test  # noqa: E402
from pettingzoo.utils.conversions import parallel_to_aec  # noqa: E402

from guardsim.envs import ACTIONS, CHANNELS, CoverageEnv, coverage_parallel_env  # noqa: E402
from guardsim.grid import DIRECTIONS  # noqa: E402
from guardsim.motion import run_episode  # noqa: E402
from guardsim.planners import make_planner  # noqa: E402
from guardsim.planners.base import STAY, EpisodeSetup, GuardState  # noqa: E402
from guardsim.render.palette import GUARD_COLOURS  # noqa: E402
from guardsim.simulation import Simulation  # noqa: E402
from tests.common import REPO, SQUARE_WITH_HOLE, level_from  # noqa: E402

SQUARE = str(REPO / "levels" / "square.json")
SEEN, GOAL, IN_VIEW, GUARD, TEAMMATES = (
    CHANNELS.index(name) for name in ("seen", "goal", "in_view", "guard", "teammates")
)


@contextmanager
def no_warnings() -> Iterator[None]:
    """Every warning is an error, except the one guardsim gives for PettingZoo's made-up reset option."""
    with warnings.catch_warnings():
        warnings.simplefilter("error")
        warnings.filterwarnings("ignore", message=r"guardsim\.envs: reset options \['options'\] ignored")
        yield


def make(level: Any = SQUARE, **options: Any) -> CoverageEnv:
    env = gymnasium.make("guardsim/Coverage-v0", level=level, **options).unwrapped
    assert isinstance(env, CoverageEnv)
    return env


@pytest.mark.parametrize(
    "options",
    [{}, {"crop": 3, "normalize": False, "render_mode": "rgb_array"}],
    ids=["defaults", "crop-raw-reward-rgb"],
)
def test_gymnasium_checker_passes_without_warnings(options: dict[str, Any]) -> None:
    with no_warnings():
        check_env(make(**options))


def test_pettingzoo_checker_passes_on_the_square() -> None:
    with no_warnings():
        parallel_api_test(coverage_parallel_env(level=SQUARE, guards=2), num_cycles=40)


def test_pettingzoo_checker_passes_through_episode_ends() -> None:
    # A short step limit on a small room: episodes end (covered or truncated) inside the cycles.
    env = coverage_parallel_env(level=level_from(SQUARE_WITH_HOLE), guards=3, max_steps=12)
    with no_warnings():
        parallel_api_test(env, num_cycles=50)
    assert env.agents == []


def test_aec_conversion_passes_pettingzoo_api_test() -> None:
    env = parallel_to_aec(coverage_parallel_env(level=level_from(SQUARE_WITH_HOLE), guards=2, max_steps=10))
    with no_warnings():
        # The AEC test advises Box or Discrete observations; ours are a Dict (planes and heading).
        warnings.filterwarnings("ignore", message="Observation is not a NumPy array")
        warnings.filterwarnings("ignore", message="Observation space for each agent probably should be")
        api_test(env, num_cycles=30)


def test_reset_starts_where_guardsim_play_and_bench_start() -> None:
    env = make()
    scene = env.task.scene
    for seed in (0, 7):
        env.reset(seed=seed)
        for episode in range(3):
            if episode:
                env.reset()
            reference = Simulation(scene, "ripplefront")
            reference.reset(seed=seed, episode=episode)
            assert (env.simulation.cells, env.simulation.headings) == (reference.cells, reference.headings)
    env.reset(seed=7, options={"episode": 2})
    assert env.task.episode == 2
    env.reset()
    assert env.task.episode == 3
    _, info = env.reset(options={"start": (5, 6), "heading": 1})
    assert info["cell"] == (5, 6) and env.simulation.headings == [1]


def test_different_seeds_give_different_starts() -> None:
    env = make()
    starts = {(tuple(env.reset(seed=seed)[1]["cell"]), env.simulation.headings[0]) for seed in range(6)}
    assert len(starts) > 1


def test_unknown_reset_option_is_named_in_a_warning() -> None:
    env = make(level_from(SQUARE_WITH_HOLE))
    with pytest.warns(UserWarning, match=r"reset options \['epsiode'\] ignored"):
        env.reset(seed=0, options={"epsiode": 3})


def assert_same(first: Any, second: Any) -> None:
    assert data_equivalence(first, second, exact=True)


def test_same_seed_same_observations_side_by_side() -> None:
    first, second = make(crop=4), make(crop=4)
    actions = np.random.default_rng(1).integers(len(ACTIONS), size=150)
    assert_same(first.reset(seed=11), second.reset(seed=11))
    for number, action in enumerate(actions):
        if number == 100:
            # An unseeded reset continues the seeded batch the same way in both.
            assert_same(first.reset(), second.reset())
            continue
        assert_same(first.step(action), second.step(action))
    other = make(crop=4)
    assert not data_equivalence(other.reset(seed=12)[0], make(crop=4).reset(seed=11)[0])


def test_team_same_seed_same_observations_side_by_side() -> None:
    first = coverage_parallel_env(level=SQUARE, guards=2)
    second = coverage_parallel_env(level=SQUARE, guards=2)
    assert_same(first.reset(seed=3), second.reset(seed=3))
    rng = np.random.default_rng(2)
    for _ in range(80):
        actions = {agent: int(rng.integers(len(ACTIONS))) for agent in first.agents}
        assert_same(first.step(actions), second.step(actions))
    assert_same(first.state(), second.state())
    assert first.state_space.contains(first.state())
    with no_warnings():
        parallel_seed_test(lambda: coverage_parallel_env(level=SQUARE, guards=2), num_cycles=20)


def ripplefront_action(planner: Any, observation: dict[str, Any], info: dict[str, Any], grid: Any) -> int:
    """The action RippleFront would take, decided on what the environment hands the agent."""
    planes = observation["grid"]
    state = GuardState(
        info["tick"],
        grid.flat(*info["cell"]),
        int(observation["heading"]),
        planes[SEEN].ravel().astype(bool),
        planes[GOAL].ravel().astype(bool),
    )
    return action_of(planner.next_move(state))


def action_of(move: int | None) -> int:
    """The environment's action for a planner's move."""
    assert move is not None, "the planner is stuck"
    return 0 if move == STAY else move + 1


@pytest.mark.parametrize("seed", [0, 5])
def test_agent_following_ripplefront_covers_in_the_planners_steps(seed: int) -> None:
    env = make(step_cost=0.5)
    scene = env.task.scene
    expected = run_episode(scene, seed=seed, episode=0, planner="ripplefront")
    assert expected.outcome == "covered"

    observation, info = env.reset(seed=seed)
    planner = make_planner("ripplefront")
    goal = observation["grid"][GOAL].ravel().astype(bool)
    planner.reset(EpisodeSetup(scene.grid, goal, scene.vision(), np.random.default_rng(0)))
    seen_at_start = info["newly_seen"]
    rewards, steps, terminated, truncated = [], 0, False, False
    while not (terminated or truncated):
        action = ripplefront_action(planner, observation, info, scene.grid)
        observation, reward, terminated, truncated, info = env.step(action)
        rewards.append(reward)
        steps += 1
    trace = env.simulation.trace()
    assert (terminated, truncated, info["outcome"]) == (True, False, "covered")
    assert steps == len(expected.path) - 1
    assert trace.path == expected.path and trace.headings == expected.headings
    assert np.array_equal(trace.first_seen, expected.first_seen)
    goal_cells = expected.reachable
    assert sum(rewards) == pytest.approx((goal_cells - seen_at_start - 0.5 * steps) / goal_cells)


def test_team_following_ripplefront_matches_the_team_episode() -> None:
    env = coverage_parallel_env(level=SQUARE, guards=2)
    expected = run_episode(env.task.scene, seed=4, episode=0, planner="ripplefront", guards=2)
    observations, infos = env.reset(seed=4)
    grid = env.task.scene.grid
    planners = [make_planner("ripplefront") for _ in range(2)]
    goal = observations["guard_0"]["grid"][GOAL].ravel().astype(bool)
    for number, planner in enumerate(planners):
        planner.reset(EpisodeSetup(grid, goal, env.task.scene.vision(), np.random.default_rng(0), number, 2))
    steps = 0
    while env.agents:
        team = tuple((grid.flat(*infos[agent]["cell"]), int(observations[agent]["heading"])) for agent in env.agents)
        actions = {}
        for number, (agent, planner) in enumerate(zip(env.agents, planners)):
            planes = observations[agent]["grid"]
            state = GuardState(infos[agent]["tick"], team[number][0], team[number][1],
                               planes[SEEN].ravel().astype(bool), goal, number, team)  # fmt: skip
            actions[agent] = action_of(planner.next_move(state))
        observations, _, terminated, _, infos = env.step(actions)
        steps += 1
    assert terminated == {"guard_0": True, "guard_1": True}
    assert steps == len(expected.path) - 1
    assert env.simulation.trace().guard_paths == expected.guard_paths


def test_moves_follow_the_mask_and_blocked_moves_stay() -> None:
    env = make(level_from(SQUARE_WITH_HOLE))
    _, info = env.reset(seed=2)
    rng = np.random.default_rng(3)
    blocked = moved = 0
    for _ in range(200):
        action = int(rng.integers(len(ACTIONS)))
        before, heading, mask = info["cell"], env.simulation.headings[0], info["action_mask"]
        assert np.array_equal(env.action_masks(), mask)
        _, _, terminated, truncated, info = env.step(action)
        if action == 0 or not mask[action]:
            blocked += action != 0
            assert (info["cell"], env.simulation.headings[0]) == (before, heading)
        else:
            moved += 1
            dcol, drow = DIRECTIONS[action - 1]
            assert info["cell"] == (before[0] + dcol, before[1] + drow)
            assert env.simulation.headings[0] == action - 1
        if terminated or truncated:
            _, info = env.reset()
    assert blocked and moved


def test_observation_planes_and_crop() -> None:
    full, cropped = make(), make(crop=5)
    observation, _ = full.reset(seed=1, options={"start": (1, 1), "heading": 0})
    window, _ = cropped.reset(seed=1, options={"start": (1, 1), "heading": 0})
    planes = observation["grid"]
    simulation = full.simulation
    assert planes.shape == (len(CHANNELS), *simulation.scene.grid.shape) and planes.dtype == np.uint8
    assert np.argwhere(planes[GUARD]).tolist() == [[1, 1]]
    assert not planes[TEAMMATES].any()
    assert sorted(map(tuple, np.argwhere(planes[IN_VIEW])[:, ::-1].tolist())) == sorted(simulation.visible_cells())
    assert np.array_equal(planes[SEEN].astype(bool), simulation.seen)
    # The window is centred on the guard; what lies past the grid's edge reads 0 everywhere.
    assert window["grid"].shape == (len(CHANNELS), 11, 11)
    assert window["grid"][GUARD, 5, 5] == 1
    assert not window["grid"][:, :4, :].any() and not window["grid"][:, :, :4].any()
    assert np.array_equal(window["grid"][:, 4:, 4:], planes[:, :7, :7])


def test_team_observations_show_teammates() -> None:
    env = coverage_parallel_env(level=SQUARE, guards=3)
    observations, infos = env.reset(seed=0, options={"starts": [(1, 1), (4, 2), (1, 1)], "headings": [0, 1, 2]})
    assert [infos[agent]["cell"] for agent in env.agents] == [(1, 1), (4, 2), (1, 1)]
    assert np.argwhere(observations["guard_1"]["grid"][TEAMMATES]).tolist() == [[1, 1]]
    assert np.argwhere(observations["guard_0"]["grid"][TEAMMATES]).tolist() == [[1, 1], [2, 4]]
    assert env.state()[3].sum() == 2


def test_raw_reward_is_new_goal_cells_minus_step_cost() -> None:
    env = make(level_from(SQUARE_WITH_HOLE), normalize=False, step_cost=0.25)
    env.reset(seed=0)
    for action in (1, 2, 1, 2, 3):
        _, reward, _, _, info = env.step(action)
        assert reward == info["newly_seen"] - 0.25


def test_episode_truncates_at_the_step_limit() -> None:
    env = make(max_steps=5)
    env.reset(seed=0)
    ends = [env.step(0)[2:4] for _ in range(5)]
    assert ends == [(False, False)] * 4 + [(False, True)]


def test_rgb_frame_marks_the_guard() -> None:
    env = make(level_from(SQUARE_WITH_HOLE), render_mode="rgb_array", cell_pixels=3)
    _, info = env.reset(seed=0)
    frame = env.render()
    assert frame is not None and frame.shape == (18, 18, 3) and frame.dtype == np.uint8
    col, row = info["cell"]
    assert frame[row * 3 + 1, col * 3 + 1].tolist() == list(GUARD_COLOURS[0])  # the GIF's first guard


def test_import_without_the_rl_extra_says_what_to_install(monkeypatch: pytest.MonkeyPatch) -> None:
    for name in [name for name in sys.modules if name.startswith("guardsim.envs")]:
        monkeypatch.delitem(sys.modules, name)
    monkeypatch.setitem(sys.modules, "pettingzoo", None)
    with pytest.raises(ImportError, match=r"install guardsim\[rl\]"):
        importlib.import_module("guardsim.envs")


@pytest.mark.parametrize("start", [(0, 0), (59, 59), (58, 3), (31, 57)], ids=str)
def test_crop_is_the_padded_grid_around_the_guard(start: tuple[int, int]) -> None:
    full, cropped = make(), make(crop=3)
    planes = full.reset(seed=0, options={"start": start})[0]["grid"]
    window = cropped.reset(seed=0, options={"start": start})[0]["grid"]
    col, row = start
    padded = np.pad(planes, ((0, 0), (3, 3), (3, 3)))
    assert np.array_equal(window, padded[:, row : row + 7, col : col + 7])


def test_the_random_agent_example_runs() -> None:
    command = [
        sys.executable,
        str(REPO / "examples" / "random_agent.py"),
        SQUARE,
        "--episodes",
        "2",
        "--max-steps",
        "30",
    ]
    result = subprocess.run(command, capture_output=True, text=True, check=False, timeout=120)
    assert result.returncode == 0, result.stderr
    assert result.stdout.splitlines()[1].startswith("episode 1: step_limit after 30 steps, coverage ")


def test_heading_option_turns_the_drawn_start() -> None:
    env = make()
    _, drawn = env.reset(seed=9)
    _, turned = env.reset(seed=9, options={"heading": 2})
    assert turned["cell"] == drawn["cell"] and env.simulation.headings == [2]
    team = coverage_parallel_env(level=SQUARE, guards=2)
    with pytest.raises(ValueError, match="1 headings for 2 guards"):
        team.reset(seed=0, options={"headings": [1]})
    with pytest.raises(ValueError, match=r"headings \[4\] must be heading numbers"):
        env.reset(seed=0, options={"start": (3, 3), "heading": 4})

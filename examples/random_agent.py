"""A random agent with action masking on guardsim's Gymnasium environment, as a starting point for learning.

Run it from the repository root (needs ``pip install guardsim[rl]``)::

    python examples/random_agent.py levels/square.json --episodes 3 --max-steps 2000
"""

from __future__ import annotations

import argparse

import gymnasium

import guardsim.envs  # noqa: F401 (registers guardsim/Coverage-v0)


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("level")
    parser.add_argument("--episodes", type=int, default=3)
    parser.add_argument("--max-steps", type=int, default=2000)
    parser.add_argument("--seed", type=int, default=0)
    args = parser.parse_args()

    env = gymnasium.make("guardsim/Coverage-v0", level=args.level, max_steps=args.max_steps)
    env.action_space.seed(args.seed)
    # A learner would read the observation (the first item); a random agent needs only the mask in info.
    _, info = env.reset(seed=args.seed)
    for episode in range(args.episodes):
        total, done = 0.0, False
        while not done:
            # Sample among the moves that move the guard (stay is always allowed).
            action = env.action_space.sample(mask=info["action_mask"])
            _, reward, terminated, truncated, info = env.step(action)
            total += float(reward)
            done = terminated or truncated
        print(
            f"episode {episode}: {info['outcome']} after {info['tick']} steps, "
            f"coverage {info['coverage']:.1%}, return {total:.3f}"
        )
        _, info = env.reset()
    env.close()


if __name__ == "__main__":
    main()

"""A 20-line training loop on barnbench.VecEnv (docs/rl.md): random search over a two-gain
steering policy, v = a, w = k * bearing of the global plan's end, scored by the mean return of
16 parallel episodes on barnbench's training worlds (never the test50 set).

    PYTHONPATH=build/python /usr/bin/python3 examples/python/vec_env_random_search.py
"""
import numpy as np
import barnbench

train = [w for w in range(300) if w % 6]  # barnbench's worlds minus test50 (0, 6, ..., 294)
env = barnbench.VecEnv(16, worlds=train, dt=0.2, max_steps=200, global_plan={}, threads=2,
                       reward={"progress": 1.0, "success": 20.0, "collision": -1.0})
rng, best, best_return = np.random.default_rng(0), np.array([0.5, 1.0]), -np.inf
for iteration in range(10):
    gains = best + rng.normal(0.0, 0.3, 2) * (iteration > 0)
    obs, _ = env.reset(seed=iteration)
    returns = []
    for _ in range(200):
        dx, dy = (obs["global_plan_end"] - obs["pose"][:, :2]).T
        bearing = np.angle(np.exp(1j * (np.arctan2(dy, dx) - obs["pose"][:, 2])))
        obs, reward, terminated, truncated, infos = env.step(np.stack([np.full(16, gains[0]), gains[1] * bearing], 1))
        if "final_info" in infos:  # episodes that ended this step (already restarted)
            returns += list(infos["final_info"]["episode_return"][infos["_final_info"]])
    if returns and np.mean(returns) > best_return:
        best, best_return = gains, np.mean(returns)
    print(f"iteration {iteration}: gains {gains.round(2)}, mean return {np.mean(returns):.2f} over {len(returns)} episodes")
print("best gains", best.round(2), "return", round(best_return, 2))

import numpy as np
import matplotlib
matplotlib.use("Agg")
import matplotlib.pyplot as plt
import frameless

scene = frameless.Scene.load("default")
reference = frameless.render(scene, size=(160, 90), spp=256)

curves = {}
for mode in ("frameless", "conventional"):
    samples, rmse = [], []
    with frameless.Engine(scene, mode=mode, size=(160, 90), threads=2,
                          deterministic=True, samples_per_tick=160 * 90 // 4) as e:
        for tick in range(120):
            e.advance()
            s = e.stats()
            samples.append(s["samples"] / (160 * 90))
            rmse.append(float(np.sqrt(np.mean((e.image() - reference) ** 2))))
    curves[mode] = (samples, rmse)

for mode, (x, y) in curves.items():
    plt.loglog(x, y, label=mode)
plt.xlabel("samples per pixel")
plt.ylabel("RMSE against 256 spp")
plt.title("default scene, 160x90, deterministic engine")
plt.legend()
plt.grid(True, which="both", alpha=0.3)
plt.savefig("docs/python_convergence.png", dpi=100)
print({m: (round(c[0][-1], 2), round(c[1][-1], 4)) for m, c in curves.items()})

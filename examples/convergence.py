#!/usr/bin/env python3
"""Run time against error for two samplers, as a notebook would do it with dacrt's Python module.

    PYTHONPATH=build/python /usr/bin/python3 examples/convergence.py [SCENE] [--plot out.png]

Renders a reference once, then each sampler at 1, 2, 4, ... samples per pixel, measures RMSE
against the reference and prints the table; with --plot (and matplotlib installed) draws error
against spp on log-log axes, where Monte Carlo error is a line of slope -1/2.
"""
import argparse
import time

import numpy as np

import dacrt


def rmse(image, reference):
    return float(np.sqrt(np.mean((image.astype(np.float64) - reference) ** 2)))


def main():
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("scene", nargs="?", default="scenes/cornell-box.gltf")
    parser.add_argument("--size", type=int, default=96, help="image width and height")
    parser.add_argument("--max-spp", type=int, default=64)
    parser.add_argument("--plot", help="write the plot here (needs matplotlib)")
    args = parser.parse_args()

    scene = dacrt.load(args.scene)
    print(f"{args.scene}: {scene.info['triangles']} triangles")
    size = dict(width=args.size, height=args.size)
    # The reference: many samples with another seed, so that its noise is independent.
    reference = dacrt.render(scene, spp=16 * args.max_spp, seed=1000, **size).astype(np.float64)

    curves = {}
    for sampler in ("sobol", "independent"):
        points = []
        spp = 1
        while spp <= args.max_spp:
            start = time.perf_counter()
            image = dacrt.render(scene, spp=spp, sampler=sampler, **size)
            seconds = time.perf_counter() - start
            points.append((spp, seconds, rmse(image, reference)))
            spp *= 2
        curves[sampler] = points
        print(f"\n{sampler}\n  spp  seconds     RMSE")
        for spp, seconds, error in points:
            print(f"{spp:5d}  {seconds:7.3f}  {error:.5f}")
        slope = np.polyfit(np.log([p[0] for p in points]), np.log([p[2] for p in points]), 1)[0]
        print(f"  slope of log RMSE against log spp: {slope:.2f}")

    if args.plot:
        try:
            import matplotlib
            matplotlib.use("Agg")
            import matplotlib.pyplot as plt
        except ImportError:
            print("matplotlib is not installed: no plot (apt-get install python3-matplotlib)")
            return
        for sampler, points in curves.items():
            plt.loglog([p[0] for p in points], [p[2] for p in points], "o-", label=sampler)
        plt.xlabel("samples per pixel")
        plt.ylabel("RMSE against the reference")
        plt.title(args.scene)
        plt.legend()
        plt.savefig(args.plot, dpi=120)
        print(f"wrote {args.plot}")


if __name__ == "__main__":
    main()

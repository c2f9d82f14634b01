"""Run time of a 1 s simulation of the default FMU through fmpy, and the share spent inside the
FMU (time in its C functions, measured around every call fmpy makes).

    .venv/bin/python tests/python/bench_fmpy.py [dist/VibratingContact.fmu]
"""

import shutil
import sys
import time

from fmpy import extract, read_model_description, simulate_fmu
from fmpy.fmi2 import FMU2Slave


def timed_slave(md, unzipdir, clock):
    fmu = FMU2Slave(
        guid=md.guid,
        unzipDirectory=unzipdir,
        modelIdentifier=md.coSimulation.modelIdentifier,
        instanceName="bench",
    )
    for name in dir(fmu):
        f = getattr(fmu, name)
        if name.startswith("fmi2") and callable(f):

            def wrap(f=f):
                def call(*args):
                    t0 = time.perf_counter()
                    try:
                        return f(*args)
                    finally:
                        clock[0] += time.perf_counter() - t0

                return call

            setattr(fmu, name, wrap())
    return fmu


def main():
    path = sys.argv[1] if len(sys.argv) > 1 else "dist/VibratingContact.fmu"
    md = read_model_description(path)
    unzipdir = extract(path)
    try:
        print("step [s]  steps   total [s]  inside FMU [s]  share")
        for step in (1e-3, 1e-5):
            clock = [0.0]
            fmu = timed_slave(md, unzipdir, clock)
            fmu.instantiate()
            t0 = time.perf_counter()
            simulate_fmu(unzipdir, stop_time=1.0, output_interval=step, fmu_instance=fmu, model_description=md, output=["F_Fx", "F_mean", "x"])
            total = time.perf_counter() - t0
            fmu.freeInstance()
            print(f"{step:8.0e}  {round(1.0 / step):6d}  {total:9.3f}  {clock[0]:13.3f}  {clock[0] / total:5.1%}")
    finally:
        shutil.rmtree(unzipdir, ignore_errors=True)


if __name__ == "__main__":
    main()

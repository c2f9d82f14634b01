"""fmpy's validation of the exported FMUs: no problem reported."""

from fmpy.validation import validate_fmu
import pytest
from fmpy import read_model_description

from conftest import DIST


def test_default_fmu_validates_without_problems(default_fmu):
    problems = validate_fmu(default_fmu)
    print(f"validate_fmu({default_fmu}): {problems}")
    assert problems == []


def test_every_exported_fmu_validates_without_problems():
    fmus = sorted(DIST.glob("*.fmu"))
    assert fmus, "no FMU in dist/: run `cargo run --release`"
    for fmu in fmus:
        assert validate_fmu(str(fmu)) == [], fmu.name


def test_capabilities_tell_the_truth(default_fmu):
    md = read_model_description(default_fmu, validate=True)
    cs = md.coSimulation
    assert md.fmiVersion == "2.0"
    assert cs.modelIdentifier == "VibratingContact"
    assert cs.canHandleVariableCommunicationStepSize
    assert cs.canGetAndSetFMUstate
    assert cs.canSerializeFMUstate
    assert cs.canNotUseMemoryManagementFunctions
    assert cs.canInterpolateInputs
    assert not cs.providesDirectionalDerivative
    assert cs.maxOutputDerivativeOrder == 1
    names = {v.name for v in md.modelVariables}
    assert {"F_d", "v_sx", "v_sy", "F_Fx", "F_mean", "P_diss", "k_t"} <= names
    # reduction is the velocity drive's output; this scene is force-driven
    assert "reduction" not in names

"""An embedded foundation's pit dug before anything is built, by the elastoplastic soil's
load steps (:class:`tankfx.iterations.load_steps.NewtonIteration`): the ground at rest loses
the support of the soil taken out (the pit's faces are relieved of their stress at rest, in
load steps), the structure standing by without stiffness; then the displacements are set to
zero, the excavated ground's stress and plastic strain kept, and the structure is built on it
free of strain."""
from __future__ import annotations

from dataclasses import replace

from .status import IterationStatus, SoilFailure


def excavate(iteration, inner, log) -> IterationStatus:
    """Dig the pit by ``iteration``'s load steps (``inner``: the chain inside it). The
    status's ``data``: the heave of the pit's bottom at its centre (m), the vertical
    reaction of the excavated ground and the load released by the pit's faces (N), for
    results.json's ``excavation`` (:func:`tankfx.results.run.excavation_record`)."""
    m, pit, newton = iteration.model, iteration.model.soil.pit, iteration.newton
    log.info("elastoplastic soil: the pit's excavation, in load steps")

    def fail(done, share, reason):
        pit.share.value = done
        a = m.scene.foundation_radius
        sv = pit.bottom_stress
        return SoilFailure(
            f"the pit cannot be excavated: the ground around it gives way (its bottom "
            f"heaving, or its sides sliding in) beyond {done:.4g} of the relief of its "
            f"stress at rest ({share:.4g} was not carried: {reason}); relieved in full "
            f"it would be sigma'_v = {sv / 1e3:.4g} kPa at its bottom, {m.scene.embedment:g} "
            f"m deep over a radius of {a:g} m; {newton.yielding_zone()}; a shallower pit "
            f"(plate.embedment), a stronger soil, or a supported pit (not modelled)",
            iteration.history)

    target = m.scene.load
    m.set_loads(iteration.start(target))        # (nothing built yet: nothing on it)
    with m.structure_absent():
        status = iteration.steps(inner, log, lambda share: setattr(pit.share, "value", share),
                                 False, fail, "the pit's stress at rest relieved in {steps} "
                                              "load steps")
    heave = -status.history[-1]["w0"]
    reaction, released = m.excavation_equilibrium()
    m.place_structure()
    m.set_loads(target)
    iteration.last = replace(status, data={"heave": heave, "released_load": released,
                                           "reaction": reaction})
    return iteration.last

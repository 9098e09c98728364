"""The registry of soil laws: the one place where a scene's ``soil.model`` word becomes a
law (:class:`tankfx.laws.soil_law.SoilLaw`). A new law is a class in its own module, and a
line here."""
from __future__ import annotations

from .cam_clay import CamClaySoil
from .drucker_prager import DruckerPragerSoil
from .duncan_chang import DuncanChang
from .kondner import Kondner
from .mohr_coulomb_soil import MohrCoulombSoil
from .soil_law import LinearElastic, SoilLaw

__all__ = ["SOIL_LAWS", "SoilLaw"]

#: soil.model -> its law, in the order the scene reference lists them
SOIL_LAWS: dict[str, type[SoilLaw]] = {law.word: law
                                       for law in (LinearElastic, Kondner, DuncanChang,
                                                   MohrCoulombSoil, DruckerPragerSoil,
                                                   CamClaySoil)}

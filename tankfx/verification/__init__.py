"""Verification: closed-form and published reference solutions
(:mod:`tankfx.verification.reference`) and the standalone rigs that are compared with them
(:mod:`tankfx.verification.rigs`)."""

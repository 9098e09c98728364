"""The finite-element models: the blocks (soil with its materials and pore pressure, structure,
interface), the tank and the flexible load that combine them, the overturning's first
harmonic, and the :class:`~tankfx.model.protocol.Model` protocol the iterations use."""

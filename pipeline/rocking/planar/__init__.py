"""Planar rocking of a uniform rectangle: the rocking kernel, the general contact model (slide, slide-rock,
free flight) and the hand-off between them, Coulomb sliding, the impact cascade's end in closed form, and the
sampled kernels of a scene's probabilities."""

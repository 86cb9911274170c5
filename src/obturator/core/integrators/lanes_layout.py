"""The lane width of the batched integrator (:mod:`.lanes`), shared with :mod:`.lane_sums`.

Lane arrays are flat and component-major with this compile-time stride
(``x[i * LANES + lane]``): with a constant stride LLVM can prove that rows do not
overlap, so the lane loops vectorise without runtime alias checks (with 2-D
arrays of runtime stride they did not vectorise at all). 16 lanes measured
fastest on the 2-core AVX2 development machine (8: slower; 32: within noise).
"""

LANES = 16

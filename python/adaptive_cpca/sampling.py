"""The CLI's `--env-sample` draws (lighting/lighting_sampler.h).

SplitMix64 from a seed: its k-th output is a mix of seed + (k + 1) times a
fixed increment, so any draw is made without the ones before it (a
DataLoader worker makes only its own). Draw i takes the uniforms 5i .. 5i+4:
map floor(u K), yaw 360 u, pitch asin(2 u - 1) and roll 360 u (rotation
"sphere"; "yaw": both 0), exposure offset J (2 u - 1); angles and offsets
rounded to 1e-6. The draws come from the compiled part where it loads
(`adaptive_cpca.draw_lighting`), else from the same arithmetic here, with
the constants of the generated contract.
"""

import math

from . import _contract as contract
from ._compiled import compiled_part

__all__ = ["Draw", "draw", "draw_lightings", "epoch_seed"]

_MASK = (1 << 64) - 1
ROTATIONS = contract.SAMPLED_ROTATIONS


def _mix(z):
    for shift, multiplier in contract.SPLITMIX_MIXES:
        z = ((z ^ (z >> shift)) * multiplier) & _MASK
    return z ^ (z >> contract.SPLITMIX_LAST_SHIFT)


def _output(seed, k):
    """The k-th (0-based) output of SplitMix64(seed)."""
    return _mix((seed + (k + 1) * contract.SPLITMIX_INCREMENT) & _MASK)


def _uniform(seed, k):
    return (_output(seed, k) >> 11) * 2.0 ** -53


def _rounded(v):
    """std::round(v steps) / steps + 0.0: halves away from zero, no -0."""
    steps = contract.DRAW_ROUNDING_STEPS
    r = v * steps
    whole = math.floor(abs(r))
    whole += 1.0 if abs(r) - whole >= 0.5 else 0.0
    return math.copysign(whole, r) / steps + 0.0


class Draw(tuple):
    """(map index, yaw, pitch, roll, exposure offset)."""

    __slots__ = ()
    map = property(lambda d: d[0])
    yaw = property(lambda d: d[1])
    pitch = property(lambda d: d[2])
    roll = property(lambda d: d[3])
    exposure = property(lambda d: d[4])


def _checked(maps, rotation, exposure_jitter):
    if maps < 1:
        raise ValueError("maps: give at least one map to draw from")
    if rotation not in ROTATIONS:
        raise ValueError(f"sampled rotation {rotation!r}: one of {', '.join(ROTATIONS)}")
    if not 0 <= exposure_jitter <= contract.MAX_EXPOSURE_JITTER:
        raise ValueError(f"exposure jitter {exposure_jitter}: not in "
                         f"0..{contract.MAX_EXPOSURE_JITTER:g} stops")


def draw(i, maps, seed=0, rotation="yaw", exposure_jitter=0.0):
    """Draw i of the stream from `seed` over `maps` maps."""
    _checked(maps, rotation, exposure_jitter)
    core = compiled_part(starts_threads=False)
    if core is not None:
        return Draw(core.draw_lighting(i, maps, seed=seed & _MASK, rotation=rotation,
                                       exposure_jitter=exposure_jitter))
    return pure_draw(i, maps, seed, rotation, exposure_jitter)


def pure_draw(i, maps, seed=0, rotation="yaw", exposure_jitter=0.0):
    """Draw i computed here (what the compiled part gives where it loads)."""
    _checked(maps, rotation, exposure_jitter)
    seed &= _MASK
    first = contract.UNIFORMS_PER_DRAW * i
    u = [_uniform(seed, first + k) for k in range(contract.UNIFORMS_PER_DRAW)]
    pitch = roll = 0.0
    if rotation == "sphere":
        pitch = _rounded(math.asin(2 * u[2] - 1) * 180 / math.pi)
        roll = _rounded(360 * u[3])
    return Draw((min(int(u[0] * maps), maps - 1), _rounded(360 * u[1]), pitch, roll,
                 _rounded(exposure_jitter * (2 * u[4] - 1))))


def draw_lightings(maps, count, seed=0, rotation="yaw", exposure_jitter=0.0):
    """The first `count` draws, as adaptive_cpca.draw_lightings gives them."""
    _checked(maps, rotation, exposure_jitter)
    core = compiled_part(starts_threads=False)
    if core is not None:
        return [Draw(d) for d in core.draw_lightings(maps, count, seed=seed & _MASK,
                                                     rotation=rotation,
                                                     exposure_jitter=exposure_jitter)]
    return [pure_draw(i, maps, seed, rotation, exposure_jitter) for i in range(count)]


def epoch_seed(seed, epoch):
    """Epoch 0 draws from `seed` itself (the CLI's stream); epoch e > 0 from
    the e-th output of SplitMix64(seed)."""
    return seed & _MASK if epoch == 0 else _output(seed & _MASK, epoch - 1)

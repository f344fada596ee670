"""The CLI's `--env-sample` draws in pure Python (lighting/lighting_sampler.h).

SplitMix64 from a seed: its k-th output is a mix of seed + (k + 1) times a
fixed increment, so any draw is made without the ones before it (a
DataLoader worker makes only its own). Draw i takes the uniforms 5i .. 5i+4:
map floor(u K), yaw 360 u, pitch asin(2 u - 1) and roll 360 u (rotation
"sphere"; "yaw": both 0), exposure offset J (2 u - 1); angles and offsets
rounded to 1e-6. The same tuples as `adaptive_cpca.draw_lightings`.
"""

import math

__all__ = ["Draw", "draw", "draw_lightings", "epoch_seed"]

_MASK = (1 << 64) - 1
_INCREMENT = 0x9E3779B97F4A7C15
ROTATIONS = ("yaw", "sphere")


def _mix(z):
    z = ((z ^ (z >> 30)) * 0xBF58476D1CE4E5B9) & _MASK
    z = ((z ^ (z >> 27)) * 0x94D049BB133111EB) & _MASK
    return z ^ (z >> 31)


def _output(seed, k):
    """The k-th (0-based) output of SplitMix64(seed)."""
    return _mix((seed + (k + 1) * _INCREMENT) & _MASK)


def _uniform(seed, k):
    return (_output(seed, k) >> 11) * 2.0 ** -53


def _rounded(v):
    """std::round(v 1e6) / 1e6 + 0.0: halves away from zero, no -0."""
    r = v * 1e6
    whole = math.floor(abs(r))
    whole += 1.0 if abs(r) - whole >= 0.5 else 0.0
    return math.copysign(whole, r) / 1e6 + 0.0


class Draw(tuple):
    """(map index, yaw, pitch, roll, exposure offset)."""

    __slots__ = ()
    map = property(lambda d: d[0])
    yaw = property(lambda d: d[1])
    pitch = property(lambda d: d[2])
    roll = property(lambda d: d[3])
    exposure = property(lambda d: d[4])


def draw(i, maps, seed=0, rotation="yaw", exposure_jitter=0.0):
    """Draw i of the stream from `seed` over `maps` maps."""
    if rotation not in ROTATIONS:
        raise ValueError(f"sampled rotation {rotation!r}: one of {', '.join(ROTATIONS)}")
    seed &= _MASK
    u = [_uniform(seed, 5 * i + k) for k in range(5)]
    pitch = roll = 0.0
    if rotation == "sphere":
        pitch = _rounded(math.asin(2 * u[2] - 1) * 180 / math.pi)
        roll = _rounded(360 * u[3])
    return Draw((min(int(u[0] * maps), maps - 1), _rounded(360 * u[1]), pitch, roll,
                 _rounded(exposure_jitter * (2 * u[4] - 1))))


def draw_lightings(maps, count, seed=0, rotation="yaw", exposure_jitter=0.0):
    """The first `count` draws, as adaptive_cpca.draw_lightings gives them."""
    if maps < 1:
        raise ValueError("maps: give at least one map to draw from")
    if not 0 <= exposure_jitter <= 20:
        raise ValueError(f"exposure jitter {exposure_jitter}: not in 0..20 stops")
    return [draw(i, maps, seed, rotation, exposure_jitter) for i in range(count)]


def epoch_seed(seed, epoch):
    """Epoch 0 draws from `seed` itself (the CLI's stream); epoch e > 0 from
    the e-th output of SplitMix64(seed)."""
    return seed & _MASK if epoch == 0 else _output(seed & _MASK, epoch - 1)

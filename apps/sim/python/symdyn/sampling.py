"""Random numbers of a sweep: per-run seeds and the distributions.

A run's numbers depend on the sweep's seed, the run's index and the factor's
name only: never on which worker made the run, in what order, nor on the
other factors. Python's own generator (random.Random, seeded from a text
through SHA-512) and the inverse distribution functions of its statistics
module are the same on every platform and Python 3 release, so a seed gives
the same samples wherever the sweep is started.

    run_seed(seed, run)  63-bit integer: SHA-256 of "symdyn-sweep:<seed>:<run>"
    u(run_seed, factor)  random.Random("<run_seed>:<factor>").random(), in (0, 1)

Latin hypercube sampling stratifies the samples of a grid point: sample s of
S falls in stratum permutation[s] of [0, 1), the permutation drawn once per
factor from random.Random("symdyn-lhs:<seed>:<factor>"), the place inside the
stratum from u; every grid point sees the same strata.
"""
import hashlib
import math
import random
import statistics

DISTRIBUTIONS = {
    # name: the members it takes (besides "distribution" and "set"), the optional ones
    "uniform": (("low", "high"), ()),
    "normal": (("mean", "sd"), ("low", "high")),
    "lognormal": (("mean", "sd"), ()),
}


def run_seed(seed, run):
    digest = hashlib.sha256(f"symdyn-sweep:{seed}:{run}".encode()).digest()
    return int.from_bytes(digest[:8], "little") >> 1


def uniform01(seed_of_run, factor):
    u = random.Random(f"{seed_of_run}:{factor}").random()
    return u if u > 0.0 else 2.0**-53  # (0, 1): the inverse functions need it open


def lhs_permutation(seed, factor, samples):
    order = list(range(samples))
    random.Random(f"symdyn-lhs:{seed}:{factor}").shuffle(order)
    return order


def quantile(distribution, u):
    """The value of a distribution (a dict of the sweep file) at probability u."""
    kind = distribution["distribution"]
    if kind == "uniform":
        low, high = distribution["low"], distribution["high"]
        return low + (high - low) * u
    if kind == "normal":
        d = statistics.NormalDist(distribution["mean"], distribution["sd"])
        low, high = distribution.get("low"), distribution.get("high")
        if low is not None or high is not None:  # truncated: u spread over [F(low), F(high)]
            a = d.cdf(low) if low is not None else 0.0
            b = d.cdf(high) if high is not None else 1.0
            u = a + (b - a) * u
            x = d.inv_cdf(min(max(u, 2.0**-53), 1.0 - 2.0**-53))
            return min(max(x, low if low is not None else x), high if high is not None else x)
        return d.inv_cdf(u)
    if kind == "lognormal":  # mean and sd of the value itself
        mean, sd = distribution["mean"], distribution["sd"]
        sigma2 = math.log1p((sd / mean) ** 2)
        mu = math.log(mean) - sigma2 / 2.0
        return math.exp(mu + math.sqrt(sigma2) * statistics.NormalDist().inv_cdf(u))
    raise AssertionError(f"distribution {kind} not handled")

"""Pieces of LIGGGHTS input that the tests, the benchmarks and the drivers
share: the opening lines of a granular deck and property/global blocks."""


def hooke_materials(kn, kt, gamman=0.0, gammat=0.0, mu=0.5, ntypes=1, extra=""):
    """property/global block for `model hooke/stiffness` with identical
    values for every type pair."""
    pairs = ntypes * ntypes

    def matrix(value):
        return " ".join([repr(float(value))] * pairs)

    return f"""
fix m_kn all property/global kn peratomtypepair {ntypes} {matrix(kn)}
fix m_kt all property/global kt peratomtypepair {ntypes} {matrix(kt)}
fix m_gn all property/global gamman peratomtypepair {ntypes} {matrix(gamman)}
fix m_gt all property/global gammat peratomtypepair {ntypes} {matrix(gammat)}
fix m_mu all property/global coefficientFriction peratomtypepair {ntypes} {matrix(mu)}
{extra}
"""


def per_pair(name, value, ntypes=1):
    values = " ".join([repr(float(value))] * (ntypes * ntypes))
    return f"fix m_{name} all property/global {name} peratomtypepair {ntypes} {values}\n"


def granular_setup(dimension=3, boundary="f f f"):
    """The lines every deck of ours starts with: SI units, spheres (discs in
    2D) with an atom map, and the ghost velocities granular contacts need."""
    return f"""units si
dimension {dimension}
atom_style sphere
atom_modify map array
boundary {boundary}
newton off
communicate single vel yes"""

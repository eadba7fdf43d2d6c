"""The rules across the dynamics.* and contact.* parameters of a cam config (the schema's).

A spring, a preload, damping or a load act on a moving follower train: without its mass (arm
inertia) they are refused, as they would silently turn the dynamics off. With one, the contact
needs a face width and moduli, and a train stiffness must give a natural frequency of at least
the smallest meaningful one.
"""
from __future__ import annotations

from typing import Any, Mapping

from ..dynamics.train import train_frequency
from ..errors import InvalidParameter
from .parameters import SPECS

#: The dynamics.* parameters that describe forces on a moving mass: they need one.
FORCE_PARAMETERS = ('dynamics.spring_rate', 'dynamics.spring_preload', 'dynamics.damping_ratio',
                    'dynamics.external_force')


def check_dynamics(values: Mapping[str, Any], oscillating: bool) -> str:
    """Check the rules (see the module) on checked flat values; return the name of the
    follower's inertia: dynamics.mass, or dynamics.arm_inertia for an oscillating follower."""
    follower_type = values['follower.type']
    name, other, unit = (('dynamics.arm_inertia', 'dynamics.mass', 'kg m^2') if oscillating
                         else ('dynamics.mass', 'dynamics.arm_inertia', 'kg'))
    if values[other]:
        raise InvalidParameter(other, values[other],
                               f'a {follower_type} follower takes {name} ({unit}) instead')
    inertia = values[name]
    if not inertia:
        for force in FORCE_PARAMETERS:
            if values[force]:
                raise InvalidParameter(force, values[force], f'needs {name} > 0 ({unit}): it '
                                       'acts on the moving follower train (or use 0.0)')
    else:
        for poisson in ('contact.cam_poisson', 'contact.follower_poisson'):
            if not values[poisson] < 0.5:
                raise InvalidParameter(poisson, values[poisson], 'must be in [0, 0.5)')
        for positive in ('contact.face_width', 'contact.cam_modulus', 'contact.follower_modulus'):
            if not values[positive] > 0.0:
                raise InvalidParameter(positive, values[positive],
                                       f'must be > 0 when {name} is given (the contact stress '
                                       'needs it)')
        if values['contact.friction'] and follower_type.endswith('roller'):
            raise InvalidParameter('contact.friction', values['contact.friction'],
                                   'applies to flat faces only (a roller rolls); use 0.0')
    _check_train(values, name, inertia)
    return name


def _check_train(values: Mapping[str, Any], inertia_name: str, inertia: float) -> None:
    """Check the follower train: a frequency or a stiffness (with an inertia), not both."""
    stiffness = values['dynamics.train_stiffness']
    if values['dynamics.train_natural_frequency'] and stiffness:
        raise InvalidParameter('dynamics.train_stiffness', stiffness,
                               'give dynamics.train_natural_frequency or '
                               'dynamics.train_stiffness, not both')
    if stiffness and not inertia:
        raise InvalidParameter('dynamics.train_stiffness', stiffness,
                               f'needs {inertia_name} to give a natural frequency (or give '
                               'dynamics.train_natural_frequency instead)')
    least = SPECS['dynamics.train_natural_frequency'].least
    frequency = train_frequency(values, inertia)
    if stiffness and least is not None and frequency < least:
        raise InvalidParameter('dynamics.train_stiffness', stiffness,
                               f'gives a natural frequency of {frequency:.3g} Hz with '
                               f'{inertia_name} {inertia:g}: must give at least {least:g} Hz')
    if values['dynamics.compensate'] and not frequency:
        raise InvalidParameter('dynamics.compensate', values['dynamics.compensate'],
                               'needs the follower train: give '
                               'dynamics.train_natural_frequency or dynamics.train_stiffness')

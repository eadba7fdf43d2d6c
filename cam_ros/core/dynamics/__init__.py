"""Dynamics: follower forces, spring, jump, camshaft torque and Hertz contact stress."""

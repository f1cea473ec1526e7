"""Sample hawt_msgs messages for the tests: every message type, every field a distinct value.

``filled(kind, i)`` is the same message wherever it is made (a publisher process, the test
that reads the bag back, the echo test), so a test can rebuild what another process sent.
"""
import random

from builtin_interfaces.msg import Time

MESSAGE_TYPES = ("BladeLoads", "TurbineState", "HarmonicLoads", "HarmonicPitch", "CollectivePitch", "BladePitch",
                 "PitchCommand", "ControlEvent", "ControllerSwitch", "ControllerState", "PlantDescription")
INTERFACE_NAMES = ("collective_pitch", "generator_torque", "blade_pitch", "harmonic/1", "harmonic/2", "harmonic/12")


def filled(kind, index: int, blades: int = 3):
    """Message ``index`` of ``kind``: every field a distinct value; strings of varying length; arrays of ``blades``."""
    rng = random.Random(f"{kind.__name__}-{index}-{blades}")
    msg = kind()
    for field, type_name in kind.get_fields_and_field_types().items():
        if type_name == "std_msgs/Header":
            msg.header.stamp = Time(sec=1000 + index, nanosec=rng.randrange(10**9))
            msg.header.frame_id = "f" * rng.randrange(5)
        elif field == "step":
            msg.step = index
        elif type_name == "sequence<double>":
            setattr(msg, field, [rng.uniform(-1e7, 1e7) for _ in range(blades)])
        elif type_name == "double":
            setattr(msg, field, rng.uniform(-1e7, 1e7))
        elif type_name.startswith("uint"):
            setattr(msg, field, rng.randrange(2 ** int(type_name[4:])))
        elif type_name == "string":
            setattr(msg, field, f"{field} {rng.random()} ψ"[: rng.randrange(1, 30)])
        elif type_name == "sequence<string>" and field == "interfaces":
            setattr(msg, field, rng.sample(INTERFACE_NAMES, rng.randrange(4)))  # claimed interface names
        elif type_name == "sequence<string>" and field.endswith("_interfaces"):
            # one entry per controller of the list before it (activate, deactivate): its claims joined by spaces
            setattr(msg, field, [" ".join(rng.sample(INTERFACE_NAMES, rng.randrange(1, 3)))
                                 for _ in getattr(msg, field[:-len("_interfaces")])])
        elif type_name == "sequence<string>":
            setattr(msg, field, [f"/wt{rng.randrange(9)}/ipc_h{i}" for i in range(rng.randrange(4))])
        elif type_name.startswith("sequence<uint"):
            setattr(msg, field, [rng.randrange(2 ** int(type_name[13:-1])) for _ in range(blades)])
        elif type_name == "boolean":
            setattr(msg, field, bool(index % 2))
        else:
            raise AssertionError(f"{kind.__name__}.{field}: no filler for {type_name}")
    return msg

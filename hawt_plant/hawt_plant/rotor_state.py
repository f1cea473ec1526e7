"""What a plant's rotor does, a name the parameter table (:mod:`hawt_plant.plant_setup`) and the model
(:class:`hawt_plant.model.ModelConfig`) share without the model's imports."""

__all__ = ["ROTOR_STATES"]

ROTOR_STATES = ("operating", "idling", "parked")
"""What the rotor does (:mod:`hawt_plant.model`'s notes): runs on its commands, idles at feather with the generator
off, or is parked by the brake."""

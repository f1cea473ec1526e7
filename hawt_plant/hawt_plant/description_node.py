"""The ``plant_description`` node: ``plant/description`` without a simulated plant.

For graphs whose measurements come from elsewhere — a replayed bag (``hawt replay``), a
turbine on hardware — the controllers still take dt and B from ``plant/description``;
this node publishes it (reliable, transient local) for a turbine file and step and
otherwise does nothing.
"""
from hawt_msgs.msg import PlantDescription
from rclpy.node import Node

from hawt_core.topics import PLANT_DESCRIPTION
from hawt_plant.plant_setup import DESCRIPTION_PARAMETERS as PARAMETERS
from hawt_plant.turbine import nrel_5mw, turbine_from
from hawt_node.node_main import node_entry_point
from hawt_node.parameters import declare_parameters
from hawt_node.qos import LATCHED

__all__ = ["PlantDescriptionNode", "PARAMETERS", "main"]

class PlantDescriptionNode(Node):
    """Publishes the description of a turbine file once, latched."""

    PARAMETERS = PARAMETERS

    def __init__(self, **node_kwargs) -> None:
        super().__init__("plant_description", **node_kwargs)
        values = declare_parameters(self, PARAMETERS)
        turbine = turbine_from(values["turbine_file"]) if values["turbine_file"] else nrel_5mw()
        self.publisher = self.create_publisher(PlantDescription, PLANT_DESCRIPTION, LATCHED)
        self.publisher.publish(PlantDescription(**turbine.description(values["dt"]).as_fields()))


main = node_entry_point(PlantDescriptionNode)

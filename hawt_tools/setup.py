from glob import glob

from setuptools import find_packages, setup

package_name = 'hawt_tools'

setup(
    name=package_name,
    version='0.1.0',
    packages=find_packages(exclude=['test']),
    package_data={package_name: ['**/*.yaml', '**/*.csv']},
    data_files=[
        ('share/ament_index/resource_index/packages', ['resource/' + package_name]),
        ('share/' + package_name, ['package.xml']),
        ('share/' + package_name + '/launch', glob('launch/*.yaml')),
        ('share/' + package_name + '/foxglove', glob('foxglove/*.json')),
    ],
    # What a pip install into a venv without ROS needs (colcon builds with --no-deps; the versions are
    # requirements-lock.txt's: pip install -c requirements-lock.txt ./hawt_core ...).
    install_requires=[
        'hawt_core',
        'hawt_plant',
        'hawt_controllers',
        'hawt_bag',
        'hawt_analysis',
        'numpy',
        'PyYAML',
        'pandas',
        'dask',
        'distributed',
    ],
    zip_safe=True,
    maintainer='hawt developers',
    maintainer_email='hawt@example.com',
    description='The hawt command, node-graph launcher and example nodes.',
    license='Apache-2.0',
    entry_points={
        # What each executable is to the engines (hawt_core.node_role).
        'hawt.nodes': [
            'bridge_plant = hawt_tools.discon_bridge:BRIDGE_PLANT',
        ],
        'console_scripts': [
            'bridge_plant = hawt_tools.bridge_node:main',
            'pulse_source = hawt_tools.example_nodes:main_pulse_source',
            'relay = hawt_tools.example_nodes:main_relay',
            'counter_sink = hawt_tools.example_nodes:main_counter_sink',
            'view = hawt_tools.view_node:main',
        ],
    },
)

from glob import glob

from setuptools import find_packages, setup

package_name = 'hawt_controllers'

CONTROLLERS = {
    'cpc': 'cpc:CollectivePitchController',
    'ipc': 'ipc:HarmonicIpcController',
    'blade_sine': 'blade_sine:BladeSineController',
    'repetitive_ipc': 'repetitive_ipc:RepetitiveIpcController',
    'repetitive_cpc': 'repetitive_cpc:RepetitiveCollectiveController',
    'coleman_excitation': 'coleman_excitation:ColemanExcitationController',
    'lqg_ipc': 'lqg_ipc:LqgIpcController',
    'main_bearing_ipc': 'main_bearing_ipc:MainBearingIpcController',
    'discon': 'discon:DisconController',
}
"""The controller types this package registers: TYPE -> its plug-in module (hawt_controllers.plugins) and class."""

setup(
    name=package_name,
    version='0.1.0',
    packages=find_packages(exclude=['test']),
    package_data={package_name: ['**/*.yaml', '**/*.csv', '**/*.npz']},
    data_files=[
        ('share/ament_index/resource_index/packages', ['resource/' + package_name]),
        ('share/' + package_name, ['package.xml']),
        ('share/' + package_name + '/launch', glob('launch/*.yaml')),
    ],
    # What a pip install into a venv without ROS needs (colcon builds with --no-deps; the versions are
    # requirements-lock.txt's: pip install -c requirements-lock.txt ./hawt_core ...).
    install_requires=[
        'hawt_core',
        'hawt_plant',
        'numpy',
        'scipy',
        'PyYAML',
        'matplotlib',
    ],
    zip_safe=True,
    maintainer='hawt developers',
    maintainer_email='hawt@example.com',
    description='Collective pitch, MBC and per-harmonic IPC controllers.',
    license='Apache-2.0',
    entry_points={
        # The registry of controller types (hawt_controllers.plugins.registry): TYPE -> Controller class.
        'hawt.controllers': [f'{name} = hawt_controllers.plugins.{target}' for name, target in CONTROLLERS.items()],
        # What each executable is to the engines (hawt_core.node_role); a controller's role comes from its type.
        'hawt.nodes': ['mbc = hawt_controllers.plugins.loop_assembly:ASSEMBLER',
                       'controller_manager = hawt_controllers.plugins.switching:MANAGER',
                       'controller = hawt_controllers.plugins.registry:controller_role']
                      + [f'{name} = hawt_controllers.plugins.registry:controller_role' for name in CONTROLLERS],
        # One controller executable, and an alias named after each type for existing graphs.
        'console_scripts': ['controller = hawt_controllers.ros.controller_node:main',
                            'mbc = hawt_controllers.ros.mbc_node:main',
                            'controller_manager = hawt_controllers.ros.controller_manager_node:main']
                           + [f'{name} = hawt_controllers.ros.controller_node:main' for name in CONTROLLERS],
    },
)

from glob import glob

from setuptools import find_packages, setup

package_name = 'hawt_controllers'

setup(
    name=package_name,
    version='0.1.0',
    packages=find_packages(exclude=['test']),
    package_data={package_name: ['**/*.yaml', '**/*.csv']},
    data_files=[
        ('share/ament_index/resource_index/packages', ['resource/' + package_name]),
        ('share/' + package_name, ['package.xml']),
        ('share/' + package_name + '/launch', glob('launch/*.yaml')),
        ('share/' + package_name + '/config', glob('config/*.yaml') + glob('config/*.npz')),
    ],
    install_requires=['setuptools'],
    zip_safe=True,
    maintainer='hawt developers',
    maintainer_email='hawt@example.com',
    description='Collective pitch, MBC and per-harmonic IPC controllers.',
    license='Apache-2.0',
    entry_points={
        'console_scripts': [
            'cpc = hawt_controllers.cpc_node:main',
            'mbc = hawt_controllers.mbc_node:main',
            'ipc = hawt_controllers.ipc_node:main',
            'blade_sine = hawt_controllers.blade_sine_node:main',
            'repetitive_ipc = hawt_controllers.repetitive_ipc_node:main',
            'repetitive_cpc = hawt_controllers.repetitive_cpc_node:main',
            'coleman_excitation = hawt_controllers.coleman_excitation_node:main',
            'lqg_ipc = hawt_controllers.lqg_ipc_node:main',
            'main_bearing_ipc = hawt_controllers.main_bearing_ipc_node:main',
            'discon = hawt_controllers.discon_node:main',
            'controller_manager = hawt_controllers.controller_manager_node:main',
        ],
    },
)

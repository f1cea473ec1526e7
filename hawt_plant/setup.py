from glob import glob

from setuptools import find_packages, setup

package_name = 'hawt_plant'

setup(
    name=package_name,
    version='0.1.0',
    packages=find_packages(exclude=['test']),
    package_data={package_name: ['**/*.yaml', '**/*.csv']},
    data_files=[
        ('share/ament_index/resource_index/packages', ['resource/' + package_name]),
        ('share/' + package_name, ['package.xml']),
        ('share/' + package_name + '/launch', glob('launch/*.yaml')),
    ],
    # What a pip install into a venv without ROS needs (colcon builds with --no-deps; the versions are
    # requirements-lock.txt's: pip install -c requirements-lock.txt ./hawt_core ...).
    install_requires=[
        'hawt_core',
        'numpy',
        'scipy',
        'numba',
        'pyconturb',
        'threadpoolctl',
        'PyYAML',
    ],
    zip_safe=True,
    maintainer='hawt developers',
    maintainer_email='hawt@example.com',
    description='Wind-turbine simulator: pure-numpy model and the plant node.',
    license='Apache-2.0',
    entry_points={
        # What each executable is to the engines (hawt_core.node_role).
        'hawt.nodes': [
            'plant = hawt_plant.plant_setup:PLANT',
            'plant_description = hawt_plant.plant_setup:DESCRIPTION',
        ],
        'console_scripts': [
            'plant = hawt_plant.plant_node:main',
            'plant_description = hawt_plant.description_node:main',
        ],
    },
)

from setuptools import find_packages, setup

package_name = 'hawt_core'

setup(
    name=package_name,
    version='0.1.0',
    packages=find_packages(exclude=['test']),
    data_files=[
        ('share/ament_index/resource_index/packages', ['resource/' + package_name]),
        ('share/' + package_name, ['package.xml']),
    ],
    # What a pip install into a venv without ROS needs (colcon builds with --no-deps; the versions are
    # requirements-lock.txt's: pip install -c requirements-lock.txt ./hawt_core ...).
    install_requires=[
        'numpy',
        'pyyaml',
    ],
    zip_safe=True,
    maintainer='hawt developers',
    maintainer_email='hawt@example.com',
    description='What every hawt core and node agrees on, without ROS: topic names, command interfaces, '
                'step matching, parameter tables, node roles, the plant description, the rotor math.',
    license='Apache-2.0',
)

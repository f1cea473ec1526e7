from setuptools import find_packages, setup

package_name = 'hawt_node'

setup(
    name=package_name,
    version='0.1.0',
    packages=find_packages(exclude=['test']),
    data_files=[
        ('share/ament_index/resource_index/packages', ['resource/' + package_name]),
        ('share/' + package_name, ['package.xml']),
    ],
    install_requires=['setuptools'],
    zip_safe=True,
    maintainer='hawt developers',
    maintainer_email='hawt@example.com',
    description='What every hawt node process shares: process main, parameter declaration, events, QoS, '
                'realtime scheduling.',
    license='Apache-2.0',
)

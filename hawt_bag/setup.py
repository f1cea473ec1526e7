from setuptools import find_packages, setup

package_name = 'hawt_bag'

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
        'hawt_core',
        'numpy',
        'PyYAML',
        'mcap',
        'zstandard',
        'lz4',
    ],
    zip_safe=True,
    maintainer='hawt developers',
    maintainer_email='hawt@example.com',
    description='MCAP bags of hawt runs: writer, readers, recorder, replayer, bag analysis.',
    license='Apache-2.0',
    entry_points={
        'console_scripts': [
            'record = hawt_bag.recorder:main',
        ],
    },
)

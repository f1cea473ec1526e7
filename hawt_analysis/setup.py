from setuptools import find_packages, setup

package_name = 'hawt_analysis'

setup(
    name=package_name,
    version='0.1.0',
    packages=find_packages(exclude=['test']),
    package_data={package_name: ['**/*.yaml', '**/*.csv']},
    data_files=[
        ('share/ament_index/resource_index/packages', ['resource/' + package_name]),
        ('share/' + package_name, ['package.xml']),
    ],
    # What a pip install into a venv without ROS needs (colcon builds with --no-deps; the versions are
    # requirements-lock.txt's: pip install -c requirements-lock.txt ./hawt_core ...).
    install_requires=[
        'hawt_core',
        'hawt_bag',
        'numpy',
        'scipy',
        'matplotlib',
        'rainflow',
        'openfast-io',
    ],
    zip_safe=True,
    maintainer='hawt developers',
    maintainer_email='hawt@example.com',
    description='Load analysis of recorded runs.',
    license='Apache-2.0',
    entry_points={
        'console_scripts': [],
    },
)

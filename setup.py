"""ament_python package definition of cam_ros."""
from glob import glob

from setuptools import find_packages, setup

PACKAGE = 'cam_ros'

setup(
    name=PACKAGE,
    version='0.1.0',
    packages=find_packages(include=[PACKAGE, f'{PACKAGE}.*']),
    package_data={PACKAGE: ['py.typed', 'studio/static/*']},
    data_files=[
        ('share/ament_index/resource_index/packages', [f'resource/{PACKAGE}']),
        (f'share/{PACKAGE}', ['package.xml']),
        (f'share/{PACKAGE}/config', sorted(glob('config/*.yaml') + glob('config/*.xml'))),
        (f'share/{PACKAGE}/config/ros2_control', sorted(glob('config/ros2_control/*'))),
    ],
    python_requires='>=3.11',
    install_requires=['setuptools'],
    extras_require={
        'test': ['pytest', 'hypothesis', 'flake8', 'mypy', 'rosbags', 'mcap-ros2-support',
                 'gcodeparser'],
    },
    zip_safe=True,
    maintainer='cam_ros maintainers',
    maintainer_email='maintainers@cam-ros.dev',
    description='Disk-cam / follower design and kinematics served to ROS 2.',
    license='Apache-2.0',
    entry_points={
        'console_scripts': [
            'cam_node = cam_ros.node.process:main',
            'cam_ros = cam_ros.cli:main',
        ],
    },
)

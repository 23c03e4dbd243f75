"""``pvfilter bag``: filter the LaserScan topic of a ROS bag (rosbag2 or ROS 1).

The command is :mod:`pvfilter.bag.command`; it needs the optional ``rosbags`` package
(``pip install "pvfilter[bag]"``), which only :mod:`pvfilter.bag.bagfile` imports. The
output bag is a copy of the input with the new topics appended
(:mod:`pvfilter.bag.outputs`), the input read and the output written through the files'
layouts (:mod:`pvfilter.bag.mcap_layout`, :mod:`pvfilter.bag.mcap_append`,
:mod:`pvfilter.bag.ros1_layout`, :mod:`pvfilter.bag.ros1_append`); those modules, the
serialized fields (:mod:`pvfilter.bag.wire`) and the robot inputs
(:mod:`pvfilter.bag.robot_inputs`) are numpy and the standard library only.
"""

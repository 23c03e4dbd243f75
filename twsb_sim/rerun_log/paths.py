"""Entity paths of a recording: one place, so the loggers, the blueprint and tests agree.

``world/...`` is the 3D scene in the world frame (REP-103, z up); ``sensor/...`` is the
scan in the LiDAR's frame, drawn in a 2D view; ``plots/...`` are time series;
``events`` is the text log of scenario phases, shoves and falls.
"""

from __future__ import annotations

WORLD = "world"
HOUSE = "world/house"
HOUSE_FLOOR = "world/house/floor"
HOUSE_CEILING = "world/house/ceiling"
HOUSE_WALLS = "world/house/walls"
HOUSE_FURNITURE = "world/house/furniture"
ROBOT = "world/robot"  # Transform3D: the base frame (axle centre) in the world
ROBOT_BODY = "world/robot/body"  # the robot's geoms, static, in the base frame
ROBOT_LIDAR = "world/robot/lidar"  # static: the LiDAR frame in the base frame
SCAN_PLANE = "world/robot/lidar/scan_plane"  # static disc: the plane the beams sweep
TRAJECTORY = "world/trajectory"  # one segment per pose sample, shown up to the cursor
ODOMETRY = "world/odometry"  # the encoder odometry's positions, odom placed at the start
LIDAR_HITS = "world/lidar/points"  # real hit points, world frame, class = BeamLabel
SHOVES = "world/shoves"  # Arrows3D while a shove acts

SENSOR = "sensor"  # 2D view origin: the sensor frame drawn with x (forward) up
SENSOR_FRAME = "sensor/lidar"  # static Transform3D from the sensor frame to the drawing
SENSOR_ROBOT = "sensor/lidar/robot"  # static: the robot's footprint and heading
SENSOR_RINGS = "sensor/lidar/rings"  # static: range rings every metre
SENSOR_LABELS = "sensor/lidar/labels"  # without a filter: scan points, class = BeamLabel
SENSOR_DECISION = "sensor/lidar/decision"  # scan points, class = BeamDecision (TP/FP/FN/TN)
SENSOR_REMOVED = "sensor/lidar/removed"  # the beams the filter removed
SENSOR_CLUSTERS = "sensor/lidar/clusters"  # clustered points, class = cluster id
SENSOR_CLUSTER_BOXES = "sensor/lidar/cluster_boxes"  # removed clusters: detected or tracked
SENSOR_CLUSTER_IDS = "sensor/lidar/cluster_ids"  # their centroids: id, P(C_pv), state
SENSOR_LEVEL_VIEW = "sensor/lidar/level_view"  # the improved filter's level view per beam

PLOTS = "plots"
PLOT_PITCH = "plots/pitch"  # deg, positive = nose down
PLOT_PITCH_ESTIMATE = "plots/pitch/imu_estimate"  # deg, the robot's estimate per IMU sample
PLOT_ROLL = "plots/roll"  # deg, positive = left side up
PLOT_ROLL_ESTIMATE = "plots/roll/imu_estimate"  # deg
PLOT_PITCH_RATE = "plots/pitch_rate"  # deg/s
PLOT_VELOCITY = "plots/velocity"  # m/s: command, actual
PLOT_VELOCITY_ODOMETRY = "plots/velocity/odometry"  # m/s, the encoder odometry's twist
PLOT_ODOMETRY_ERROR = "plots/odometry_error"  # m and deg: encoder odometry against the truth
PLOT_YAW_RATE = "plots/yaw_rate"  # deg/s: command, actual
PLOT_WHEEL_TORQUE = "plots/wheel_torque"  # N·m: left, right
PLOT_BEAMS = "plots/beams"  # count: pitch-variation beams (truth), removed (filter)
PLOT_PRECISION_RECALL = "plots/precision_recall"  # per frame
PLOT_P_PV = "plots/p_pv"  # the frame's highest beam score, and P_th

EVENTS = "events"  # TextLog: phases, shoves, falls
LEGEND = "legend"  # TextDocument: what the colours mean

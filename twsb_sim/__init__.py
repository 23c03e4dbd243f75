"""A MuJoCo simulator of a two-wheeled self-balancing robot carrying a labeled 2D LiDAR."""

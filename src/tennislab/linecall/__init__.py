"""Line calling: seed 001's closed-form drop point, track fitting, ball-mark calls, cameras."""

# Plays a guardsim patrol route (Godot 3). Attach to a "Follow" PathFollow2D in the scene that
# `guardsim patrol LEVEL --out DIR --godot patrol.tscn --godot-version 3` writes; the Path2D above it
# carries the timing (see docs/patrols.md, "Godot"). tests/test_godot_export.py runs this script in
# real Godot 3 and checks it walks the route guardsim planned.
extends PathFollow2D

# Seconds since the patrol started; the follower plays in real time unless `playing` is off.
var time := 0.0
var playing := true
# Where each curve point is along the curve Godot baked (PathFollow2D's offset), measured once.
var offsets := PoolRealArray()


func _process(delta: float) -> void:
	if playing:
		time += delta
		seek(time)


# Puts the follower where the guard is `seconds` after the patrol started (guardsim's position_at).
func seek(seconds: float) -> void:
	var path: Path2D = get_parent()
	var times: PoolRealArray = path.get_meta("times")
	var waits: PoolRealArray = path.get_meta("waits")
	if offsets.size() != times.size():
		offsets = measure(path.curve)
	var headings: PoolRealArray = path.get_meta("headings")
	var mode: String = path.get_meta("loop_mode")
	var period: float = path.get_meta("period")
	var last := times.size() - 1
	var t: float = seconds + path.get_meta("phase")
	if mode != "once":
		t = fposmod(t, period)
	if mode == "ping-pong":
		var turn: float = times[last] + waits[last]
		if t > turn:
			t = times[last] - (t - turn)  # the walk back mirrors the walk out
	var i := last
	while i > 0 and times[i] > t:
		i -= 1
	var leave: float = times[i] + waits[i]
	if i == last or t <= leave:
		offset = offsets[i]
		rotation_degrees = headings[i]
	else:
		offset = lerp(offsets[i], offsets[i + 1], (t - leave) / (times[i + 1] - leave))
		var ahead: Vector2 = path.curve.get_point_position(i + 1) - path.curve.get_point_position(i)
		rotation = ahead.angle()


# The distance along the baked curve of each curve point: Godot bakes a point every bake_interval
# pixels and cuts sharp turns a little, so the baked distances, not the drawn ones, are what
# PathFollow2D takes. Between two curve points the route is straight, so the nearest baked point is
# found by walking on while the baked points come closer.
func measure(curve: Curve2D) -> PoolRealArray:
	var baked: PoolVector2Array = curve.get_baked_points()
	var found := PoolRealArray()
	var k := 0
	for i in range(curve.get_point_count()):
		var point: Vector2 = curve.get_point_position(i)
		while k + 1 < baked.size() and baked[k + 1].distance_to(point) < baked[k].distance_to(point):
			k += 1
		found.append(k * curve.bake_interval)
	return found

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
var baked := PoolVector2Array()


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
		baked = path.curve.get_baked_points()
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
		offset = leg_offset(path.curve, i, (t - leave) / (times[i + 1] - leave))
		var ahead: Vector2 = path.curve.get_point_position(i + 1) - path.curve.get_point_position(i)
		rotation = ahead.angle()


# The distance along the baked curve of each curve point: Godot bakes a point every bake_interval
# pixels and cuts sharp turns a little, so the baked distances, not the drawn ones, are what
# PathFollow2D takes. Between two curve points the route is straight, so the nearest baked point is
# found by walking on while the baked points come closer.
func measure(curve: Curve2D) -> PoolRealArray:
	var found := PoolRealArray()
	var k := 0
	for i in range(curve.get_point_count()):
		var point: Vector2 = curve.get_point_position(i)
		while k + 1 < baked.size() and baked[k + 1].distance_to(point) < baked[k].distance_to(point):
			k += 1
		found.append(_along(baked, k, point) * curve.bake_interval)
	return found


# Where `point` falls, in baked steps, on the baked segment before or after baked point k.
func _along(baked, k: int, point: Vector2) -> float:
	if k + 1 < baked.size():
		var ahead: Vector2 = baked[k + 1] - baked[k]
		var share: float = (point - baked[k]).dot(ahead) / max(ahead.length_squared(), 1e-12)
		if share > 0.0:
			return k + min(share, 1.0)
	if k > 0:
		var behind: Vector2 = baked[k] - baked[k - 1]
		var share: float = (point - baked[k - 1]).dot(behind) / max(behind.length_squared(), 1e-12)
		return k - 1 + clamp(share, 0.0, 1.0)
	return float(k)



# The offset `share` of the way along the straight leg from curve point i to i + 1. Godot spaces its
# baked points only roughly evenly, so the offset is found where the baked points reach that far along
# the leg (a binary search between the leg's ends), not in proportion.
func leg_offset(curve: Curve2D, i: int, share: float) -> float:
	var a: Vector2 = curve.get_point_position(i)
	var leg: Vector2 = curve.get_point_position(i + 1) - a
	var length2: float = max(leg.length_squared(), 1e-12)
	var lo := int(floor(offsets[i] / curve.bake_interval))
	var hi := int(min(ceil(offsets[i + 1] / curve.bake_interval), baked.size() - 1))
	while hi - lo > 1:
		var middle := (lo + hi) / 2
		if (baked[middle] - a).dot(leg) / length2 < share:
			lo = middle
		else:
			hi = middle
	var low: float = (baked[lo] - a).dot(leg) / length2
	var high: float = (baked[hi] - a).dot(leg) / length2
	var part: float = 0.0 if high <= low else clamp((share - low) / (high - low), 0.0, 1.0)
	return (lo + part) * curve.bake_interval

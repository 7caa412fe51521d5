// Moves a GameObject along one guard's route from guardsim's route.json (Unity).
// Export with y up, one world unit a metre:  guardsim patrol LEVEL --out DIR --export route.json --axis y-up
// (or --units pixels --pixels-per-unit N --axis y-up and divide by your sprites' pixels per unit).
// Put route.json in a Resources folder as a TextAsset, attach this to the guard, set Guard (1, 2, ...).
// The rule is guardsim.patrol.export.position_at: stand `wait` seconds at each waypoint, walk straight
// to the next, repeat by loop_mode (loop, ping-pong, once), start `phase` seconds along.
using System;
using UnityEngine;

public class GuardRoute : MonoBehaviour
{
    [Serializable] public class Waypoint { public float x, y, time, heading, wait; }
    [Serializable] public class Guard { public string loop_mode; public float phase; public Waypoint[] waypoints; }
    [Serializable] public class Route { public string units, axis; public float period_seconds; public Guard[] guards; }

    public TextAsset routeJson;
    public int guard = 1;
    Route route;
    float clock;

    void Start() { route = JsonUtility.FromJson<Route>(routeJson.text); }

    void Update()
    {
        clock += Time.deltaTime;
        Guard g = route.guards[guard - 1];
        transform.position = PositionAt(g, clock, route.period_seconds);
    }

    public static Vector3 PositionAt(Guard g, float seconds, float period)
    {
        Waypoint[] w = g.waypoints;
        int last = w.Length - 1;
        float t = seconds + g.phase;
        if (g.loop_mode != "once") t = Mathf.Repeat(t, period);
        if (g.loop_mode == "ping-pong")
        {
            float turn = w[last].time + w[last].wait;
            if (t > turn) t = w[last].time - (t - turn);  // the walk back mirrors the walk out
        }
        int i = last;
        while (i > 0 && w[i].time > t) i--;
        float leave = w[i].time + w[i].wait;
        if (i == last || t <= leave) return new Vector3(w[i].x, w[i].y, 0f);
        float share = (t - leave) / (w[i + 1].time - leave);
        return new Vector3(Mathf.Lerp(w[i].x, w[i + 1].x, share), Mathf.Lerp(w[i].y, w[i + 1].y, share), 0f);
    }
}

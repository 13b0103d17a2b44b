// The few UnityEngine types docs/streaming.md's AnnexReceiver uses, so that the script
// compiles and runs under Mono in a test (tests/runtime/test_unity_receiver.cpp). Only
// what the script needs, with Unity's semantics for it.
using System;

namespace UnityEngine
{
    public class Object { }

    public class Component : Object { }

    public class Behaviour : Component { }

    public class MonoBehaviour : Behaviour { }

    public struct Vector3
    {
        public float x, y, z;
        public Vector3(float x, float y, float z) { this.x = x; this.y = y; this.z = z; }
        public static readonly Vector3 zero = new Vector3(0, 0, 0);
        public static Vector3 operator +(Vector3 a, Vector3 b) { return new Vector3(a.x + b.x, a.y + b.y, a.z + b.z); }
    }

    public struct Quaternion
    {
        public float x, y, z, w;
        public Quaternion(float x, float y, float z, float w) { this.x = x; this.y = y; this.z = z; this.w = w; }
        public static Quaternion identity { get { return new Quaternion(0, 0, 0, 1); } }

        public static Quaternion operator *(Quaternion a, Quaternion b)
        {
            return new Quaternion(
                a.w * b.x + a.x * b.w + a.y * b.z - a.z * b.y,
                a.w * b.y - a.x * b.z + a.y * b.w + a.z * b.x,
                a.w * b.z + a.x * b.y - a.y * b.x + a.z * b.w,
                a.w * b.w - a.x * b.x - a.y * b.y - a.z * b.z);
        }

        public static Vector3 operator *(Quaternion q, Vector3 v)
        {
            // v + 2 w (u x v) + 2 u x (u x v)
            float ux = q.x, uy = q.y, uz = q.z;
            float cx = uy * v.z - uz * v.y, cy = uz * v.x - ux * v.z, cz = ux * v.y - uy * v.x;
            float ccx = uy * cz - uz * cy, ccy = uz * cx - ux * cz, ccz = ux * cy - uy * cx;
            return new Vector3(v.x + 2 * (q.w * cx + ccx), v.y + 2 * (q.w * cy + ccy), v.z + 2 * (q.w * cz + ccz));
        }

        // Unity's order: z, then x, then y (degrees).
        public static Quaternion Euler(Vector3 e)
        {
            Func<Vector3, float, Quaternion> axis = (a, deg) =>
            {
                double h = deg * Math.PI / 360.0;
                float s = (float)Math.Sin(h);
                return new Quaternion(a.x * s, a.y * s, a.z * s, (float)Math.Cos(h));
            };
            return axis(new Vector3(0, 1, 0), e.y) * axis(new Vector3(1, 0, 0), e.x) * axis(new Vector3(0, 0, 1), e.z);
        }
    }

    public class Transform : Component
    {
        public Vector3 position = Vector3.zero;
        public Quaternion rotation = Quaternion.identity;
        public Vector3 localScale = new Vector3(1, 1, 1);
        public Vector3 TransformPoint(Vector3 p)
        {
            var s = new Vector3(p.x * localScale.x, p.y * localScale.y, p.z * localScale.z);
            return position + rotation * s;
        }
    }

    public class GameObject : Object
    {
        public readonly Transform transform = new Transform();
        public bool activeSelf { get; private set; } = true;
        public string name;
        public GameObject(string name) { this.name = name; }
        public void SetActive(bool value) { activeSelf = value; }
    }

    public static class Debug
    {
        public static void LogWarning(object message) { Console.Error.WriteLine("warning: " + message); }
    }
}

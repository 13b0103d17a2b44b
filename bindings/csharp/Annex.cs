// Annex for C# (Unity, Godot .NET, plain .NET/Mono): P/Invoke declarations of the C API
// (annex/annex.h, libannex_c) and a small wrapper over them. No Unity dependency: the
// pose types are plain structs; docs/embedding.md shows a MonoBehaviour built on them.
//
// Threading (as annex.h): a Spec may be shared by threads; one Session or Scanner must be
// used by one thread at a time (the render loop's). Dispose() every handle, or let the
// finalizer do it.
using System;
using System.Collections.Generic;
using System.Runtime.InteropServices;
using System.Text;

namespace Annex
{
    public enum Status
    {
        Ok = 0, InvalidArgument = 1, ParseError = 2, IoError = 3, ScanFailed = 4,
        BufferTooSmall = 5, AbiMismatch = 6, InternalError = 7
    }

    public enum TrackingState { Tracking = 0, Held = 1, Reinit = 2, Lost = 3 }
    public enum EventKind { Annexed = 0, Lost = 1, Released = 2 }

    /// <summary>A failed call: the library's message ("file:line:col: error: ..."), status and place.</summary>
    public sealed class AnnexException : Exception
    {
        public Status Status { get; }
        public string Origin { get; }
        public int Line { get; }
        public int Column { get; }
        internal AnnexException(Status status, string message, string origin, int line, int column)
            : base(message)
        {
            Status = status; Origin = origin; Line = line; Column = column;
        }
    }

    [StructLayout(LayoutKind.Sequential)]
    public struct Intrinsics
    {
        public int Width, Height;
        public double Fx, Fy, Cx, Cy;
    }

    [StructLayout(LayoutKind.Sequential)]
    public struct ScanParams
    {
        public double CameraTiltDeg, MaxPlaneAngleDeg, MinHeightM, MaxHeightM, MaxDepthM,
            ClusterToleranceM;
        public int MinClusterPoints, Threads;
    }

    [StructLayout(LayoutKind.Sequential)]
    public struct SessionParams
    {
        public ScanParams Scan;
        public int ScanEvery, ReleaseAfterFrames, Threads;
        public double MinVote;
        public int BackgroundScan, HasIntrinsics;
        public Intrinsics Intrinsics;

        /// <summary>The library's defaults (background scanning on).</summary>
        public static SessionParams Defaults()
        {
            Native.annex_session_params_init(out SessionParams p);
            return p;
        }
    }

    [StructLayout(LayoutKind.Sequential)]
    public struct FrameInfo
    {
        public int Frame, ScanApplied, ScanFrame, ScanFailed;
        public IntPtr ScanErrorPtr;
        public int Matched;
        public double ScanMs, TrackMs, TotalMs;
    }

    /// <summary>A point or direction, Unity-free (x, y, z).</summary>
    public struct Vec3
    {
        public double X, Y, Z;
        public Vec3(double x, double y, double z) { X = x; Y = y; Z = z; }
        public override string ToString() => $"({X:F4}, {Y:F4}, {Z:F4})";
    }

    /// <summary>A rotation in Unity's component order (x, y, z, w).</summary>
    public struct Quat
    {
        public double X, Y, Z, W;
        public Quat(double x, double y, double z, double w) { X = x; Y = y; Z = z; W = w; }
    }

    /// <summary>A model pose: scale along the model's axes, then rotate, then move.</summary>
    public struct Pose
    {
        public Vec3 Position;
        public Quat Rotation;
        public Vec3 Scale;
    }

    public sealed class PhysicalPrimitive
    {
        public string Shape;
        public Dictionary<string, double> Dimensions = new Dictionary<string, double>();
        public Vec3 Center, Axis;
        /// <summary>A plane's size_x direction, in its plane; (0, 0, 0) for other shapes.</summary>
        public Vec3 XAxis;
        public double Fit;
    }

    public sealed class PhysicalObject
    {
        public string Id;
        /// <summary>The id of the object it stands on; "" on the support itself.</summary>
        public string OnObject = "";
        public int PointCount;
        public double Fit;
        public List<PhysicalPrimitive> Primitives = new List<PhysicalPrimitive>();
        public string Shape => Primitives.Count > 0 ? Primitives[0].Shape : "unknown";
    }

    public sealed class MatchEntry
    {
        public string Virtual;
        public string Physical;  // null: virtual-only
        public double Vote;
    }

    public sealed class AnnexedObject
    {
        public string Virtual, Physical;
        public int VirtualIndex, MatchedFrame;
        public TrackingState State;
        public double Confidence, Vote;
        /// <summary>Sensor frame: right-handed, metres, x right, y down, z forward.</summary>
        public Pose SensorPose;
        /// <summary>Unity's left-handed, y-up camera space (annex_pose_to_unity).</summary>
        public Pose UnityPose;
    }

    public struct AnnexEvent
    {
        public EventKind Kind;
        public string Virtual, Physical;
        public int Frame;
    }

    internal static class Native
    {
        const string Lib = "annex_c";

        [StructLayout(LayoutKind.Sequential)]
        internal struct Object
        {
            public IntPtr VirtualName, PhysicalId;
            public int VirtualIndex, State;
            public double Confidence, Vote;
            public double Px, Py, Pz, Qw, Qx, Qy, Qz, Sx, Sy, Sz;
            public int MatchedFrame;
        }

        [StructLayout(LayoutKind.Sequential)]
        internal struct Event
        {
            public int Kind;
            public IntPtr VirtualName, PhysicalId;
            public int Frame;
        }

        [StructLayout(LayoutKind.Sequential)]
        internal struct PhysObject
        {
            public IntPtr Id;
            public int PrimitiveCount, PointCount;
            public double Fit;
        }

        [StructLayout(LayoutKind.Sequential)]
        internal struct Primitive
        {
            public int Shape;
            public IntPtr ShapeName;
            public int DimensionCount;
            public IntPtr Name0, Name1, Name2;
            public double D0, D1, D2, Cx, Cy, Cz, Ax, Ay, Az, Fit;
        }

        [StructLayout(LayoutKind.Sequential)]
        internal struct Match
        {
            public IntPtr VirtualName, PhysicalId;
            public double Vote;
        }

        [DllImport(Lib)] internal static extern IntPtr annex_error_message(IntPtr e);
        [DllImport(Lib)] internal static extern Status annex_error_status(IntPtr e);
        [DllImport(Lib)] internal static extern IntPtr annex_error_origin(IntPtr e);
        [DllImport(Lib)] internal static extern int annex_error_line(IntPtr e);
        [DllImport(Lib)] internal static extern int annex_error_column(IntPtr e);
        [DllImport(Lib)] internal static extern void annex_error_destroy(IntPtr e);
        [DllImport(Lib)] internal static extern IntPtr annex_version_string();
        [DllImport(Lib)] internal static extern int annex_abi_version();
        [DllImport(Lib)] internal static extern Status annex_check_abi(int abi, out IntPtr e);

        [DllImport(Lib)] internal static extern Status annex_spec_load_file(byte[] path, out IntPtr spec, out IntPtr e);
        [DllImport(Lib)] internal static extern Status annex_spec_load_text(byte[] text, byte[] origin, out IntPtr spec, out IntPtr e);
        [DllImport(Lib)] internal static extern void annex_spec_destroy(IntPtr spec);
        [DllImport(Lib)] internal static extern UIntPtr annex_spec_object_count(IntPtr spec);
        [DllImport(Lib)] internal static extern IntPtr annex_spec_object_name(IntPtr spec, UIntPtr i);
        [DllImport(Lib)] internal static extern double annex_spec_object_model_scale(IntPtr spec, UIntPtr i);

        [DllImport(Lib)] internal static extern Status annex_frame_from_points(float[] xyz, int w, int h, byte[] rgb, out IntPtr frame, out IntPtr e);
        [DllImport(Lib)] internal static extern Status annex_frame_from_depth(ushort[] depth, int w, int h, ref Intrinsics k, double scale, byte[] rgb, out IntPtr frame, out IntPtr e);
        [DllImport(Lib)] internal static extern Status annex_frame_load_pcd(byte[] path, out IntPtr frame, out IntPtr e);
        [DllImport(Lib)] internal static extern void annex_frame_destroy(IntPtr frame);
        [DllImport(Lib)] internal static extern int annex_frame_width(IntPtr frame);
        [DllImport(Lib)] internal static extern int annex_frame_height(IntPtr frame);

        [DllImport(Lib)] internal static extern void annex_scan_params_init(out ScanParams p);
        [DllImport(Lib)] internal static extern Status annex_scanner_create(ref ScanParams p, out IntPtr scanner, out IntPtr e);
        [DllImport(Lib)]
        internal static extern Status annex_scanner_create_from_config(string path,
                                                                       out IntPtr scanner,
                                                                       out IntPtr e);
        [DllImport(Lib)] internal static extern void annex_scanner_destroy(IntPtr scanner);
        [DllImport(Lib)] internal static extern Status annex_scan(IntPtr scanner, IntPtr frame, out IntPtr scene, out IntPtr e);
        [DllImport(Lib)] internal static extern void annex_scene_destroy(IntPtr scene);
        [DllImport(Lib)] internal static extern UIntPtr annex_scene_object_count(IntPtr scene);
        [DllImport(Lib)] internal static extern Status annex_scene_object(IntPtr scene, UIntPtr i, out PhysObject o, out IntPtr e);
        [DllImport(Lib)] internal static extern IntPtr annex_scene_object_on(IntPtr scene, UIntPtr i);
        [DllImport(Lib)] internal static extern Status annex_scene_primitive(IntPtr scene, UIntPtr i, UIntPtr p, out Primitive o, out IntPtr e);
        [DllImport(Lib)] internal static extern UIntPtr annex_scene_surface_count(IntPtr scene);
        [DllImport(Lib)] internal static extern Status annex_scene_with_surfaces(IntPtr scene, out IntPtr both, out IntPtr e);
        [DllImport(Lib)] internal static extern int annex_scene_primitive_x_axis(IntPtr scene, UIntPtr i, UIntPtr p, [Out] double[] xAxis);

        [DllImport(Lib)] internal static extern Status annex_match_objects(IntPtr spec, IntPtr scene, out IntPtr match, out IntPtr e);
        [DllImport(Lib)] internal static extern void annex_match_destroy(IntPtr match);
        [DllImport(Lib)] internal static extern UIntPtr annex_match_count(IntPtr match);
        [DllImport(Lib)] internal static extern Status annex_match_entry_at(IntPtr match, UIntPtr i, out Match m, out IntPtr e);

        [DllImport(Lib)] internal static extern void annex_session_params_init(out SessionParams p);
        [DllImport(Lib)] internal static extern Status annex_session_create(IntPtr spec, ref SessionParams p, out IntPtr session, out IntPtr e);
        [DllImport(Lib)]
        internal static extern Status annex_session_create_with_scan_config(IntPtr spec,
                                                                            ref SessionParams p,
                                                                            string scanConfigPath,
                                                                            out IntPtr session,
                                                                            out IntPtr e);
        [DllImport(Lib)] internal static extern void annex_session_destroy(IntPtr session);
        [DllImport(Lib)] internal static extern Status annex_session_push(IntPtr session, IntPtr frame, out IntPtr e);
        [DllImport(Lib)] internal static extern Status annex_session_objects(IntPtr session, [Out] Object[] buf, UIntPtr capacity, out UIntPtr count, out IntPtr e);
        [DllImport(Lib)] internal static extern Status annex_session_events(IntPtr session, [Out] Event[] buf, UIntPtr capacity, out UIntPtr count, out IntPtr e);
        [DllImport(Lib)] internal static extern Status annex_session_frame_info(IntPtr session, out FrameInfo info, out IntPtr e);
        [DllImport(Lib)] internal static extern void annex_pose_to_unity(double[] position, double[] rotationWxyz, [Out] double[] unityPosition, [Out] double[] unityRotationXyzw);

        /// <summary>NUL-terminated UTF-8 for a C string argument.</summary>
        internal static byte[] Utf8(string s) => s == null ? null : Encoding.UTF8.GetBytes(s + "\0");

        internal static string Str(IntPtr p)
        {
            if (p == IntPtr.Zero) return null;
            int n = 0;
            while (Marshal.ReadByte(p, n) != 0) ++n;
            var bytes = new byte[n];
            Marshal.Copy(p, bytes, 0, n);
            return Encoding.UTF8.GetString(bytes);
        }

        /// <summary>Throws the call's error (and frees it) unless it succeeded.</summary>
        internal static void Check(Status status, IntPtr error)
        {
            if (status == Status.Ok) return;
            string message = error != IntPtr.Zero ? Str(annex_error_message(error)) : status.ToString();
            string origin = error != IntPtr.Zero ? Str(annex_error_origin(error)) : "";
            int line = error != IntPtr.Zero ? annex_error_line(error) : 0;
            int column = error != IntPtr.Zero ? annex_error_column(error) : 0;
            if (error != IntPtr.Zero) annex_error_destroy(error);
            throw new AnnexException(status, message, origin, line, column);
        }
    }

    /// <summary>Library-wide calls. Call CheckAbi() once before anything else.</summary>
    public static class Library
    {
        /// <summary>The C ABI these declarations are written for (ANNEX_ABI_VERSION).</summary>
        public const int AbiVersion = 1;

        public static string Version => Native.Str(Native.annex_version_string());

        public static void CheckAbi()
        {
            Native.Check(Native.annex_check_abi(AbiVersion, out IntPtr e), e);
        }
    }

    /// <summary>Base of the handle wrappers: one native handle, freed once.</summary>
    public abstract class Handle : IDisposable
    {
        internal IntPtr Ptr;
        internal Handle(IntPtr ptr) { Ptr = ptr; }
        protected abstract void Free(IntPtr ptr);
        internal IntPtr Live
        {
            get
            {
                if (Ptr == IntPtr.Zero) throw new ObjectDisposedException(GetType().Name);
                return Ptr;
            }
        }
        public void Dispose()
        {
            if (Ptr != IntPtr.Zero) Free(Ptr);
            Ptr = IntPtr.Zero;
            GC.SuppressFinalize(this);
        }
        ~Handle()
        {
            if (Ptr != IntPtr.Zero) Free(Ptr);
        }
    }

    /// <summary>A haptic spec (.haptic): the virtual objects and their primitives.</summary>
    public sealed class Spec : Handle
    {
        Spec(IntPtr p) : base(p) { }
        protected override void Free(IntPtr p) => Native.annex_spec_destroy(p);

        public static Spec Load(string path)
        {
            Native.Check(Native.annex_spec_load_file(Native.Utf8(path), out IntPtr s, out IntPtr e), e);
            return new Spec(s);
        }

        public static Spec Parse(string text, string origin = "<text>")
        {
            Native.Check(Native.annex_spec_load_text(Native.Utf8(text), Native.Utf8(origin), out IntPtr s, out IntPtr e), e);
            return new Spec(s);
        }

        public string[] Names
        {
            get
            {
                int n = (int)Native.annex_spec_object_count(Live);
                var names = new string[n];
                for (int i = 0; i < n; ++i) names[i] = Native.Str(Native.annex_spec_object_name(Ptr, (UIntPtr)i));
                return names;
            }
        }

        /// <summary>Metres per mesh unit of each virtual object (spec order; `model_scale`).</summary>
        public double[] ModelScales
        {
            get
            {
                int n = (int)Native.annex_spec_object_count(Live);
                var scales = new double[n];
                for (int i = 0; i < n; ++i) scales[i] = Native.annex_spec_object_model_scale(Ptr, (UIntPtr)i);
                return scales;
            }
        }
    }

    /// <summary>One depth frame, copied into the library.</summary>
    public sealed class Frame : Handle
    {
        Frame(IntPtr p) : base(p) { }
        protected override void Free(IntPtr p) => Native.annex_frame_destroy(p);

        /// <summary>width * height * 3 floats, row-major, sensor frame metres, NaN = no reading.</summary>
        public static Frame FromPoints(float[] xyz, int width, int height)
        {
            if (xyz == null || xyz.Length < (long)width * height * 3)
                throw new ArgumentException("xyz must hold width * height * 3 floats");
            Native.Check(Native.annex_frame_from_points(xyz, width, height, null, out IntPtr f, out IntPtr e), e);
            return new Frame(f);
        }

        /// <summary>z = depth * depthScaleM (0.001 for millimetres); 0 = no reading.</summary>
        public static Frame FromDepth(ushort[] depth, int width, int height, Intrinsics k, double depthScaleM)
        {
            if (depth == null || depth.Length < (long)width * height)
                throw new ArgumentException("depth must hold width * height values");
            Native.Check(Native.annex_frame_from_depth(depth, width, height, ref k, depthScaleM, null, out IntPtr f, out IntPtr e), e);
            return new Frame(f);
        }

        public static Frame LoadPcd(string path)
        {
            Native.Check(Native.annex_frame_load_pcd(Native.Utf8(path), out IntPtr f, out IntPtr e), e);
            return new Frame(f);
        }

        public int Width => Native.annex_frame_width(Live);
        public int Height => Native.annex_frame_height(Live);
    }

    /// <summary>Scans frames into physical objects; parameters checked at creation.</summary>
    public sealed class Scanner : Handle
    {
        Scanner(IntPtr p) : base(p) { }
        protected override void Free(IntPtr p) => Native.annex_scanner_destroy(p);

        public static ScanParams DefaultParams()
        {
            Native.annex_scan_params_init(out ScanParams p);
            return p;
        }

        public static Scanner Create() => Create(DefaultParams());

        public static Scanner Create(ScanParams p)
        {
            Native.Check(Native.annex_scanner_create(ref p, out IntPtr s, out IntPtr e), e);
            return new Scanner(s);
        }

        /// <summary>
        /// Every scan parameter from a scan config file (samples/config/scan.conf): the
        /// depth camera's noise model (<c>depth_noise stereo</c> for a RealSense), the
        /// supports, every threshold. Throws ParseError naming file:line:column.
        /// </summary>
        public static Scanner FromConfig(string path) {
          Native.Check(Native.annex_scanner_create_from_config(path, out IntPtr s, out IntPtr e),
                       e);
          return new Scanner(s);
        }

        /// <summary>The objects on the support, left to right; throws (ScanFailed) without one.</summary>
        public List<PhysicalObject> Scan(Frame frame) => Scan(frame, false);

        /// <summary>
        /// With <paramref name="surfaces"/> the objects are followed by the flat surfaces a
        /// virtual panel may lie on (s1.free, p3.top, p1.face: one plane each).
        /// </summary>
        public List<PhysicalObject> Scan(Frame frame, bool surfaces)
        {
            IntPtr scene = ScanScene(frame, surfaces);
            try { return Read(scene); }
            finally { Native.annex_scene_destroy(scene); }
        }

        /// <summary>Scans and matches in one go (the scene handle stays inside).</summary>
        public List<MatchEntry> Match(Spec spec, Frame frame) => Match(spec, frame, false);

        /// <summary>With <paramref name="surfaces"/> virtual panels vote for the scan's flat surfaces too.</summary>
        public List<MatchEntry> Match(Spec spec, Frame frame, bool surfaces)
        {
            IntPtr scene = ScanScene(frame, surfaces);
            IntPtr e;
            try
            {
                Native.Check(Native.annex_match_objects(spec.Live, scene, out IntPtr match, out e), e);
                try
                {
                    var result = new List<MatchEntry>();
                    int n = (int)Native.annex_match_count(match);
                    for (int i = 0; i < n; ++i)
                    {
                        Native.Check(Native.annex_match_entry_at(match, (UIntPtr)i, out Native.Match m, out e), e);
                        result.Add(new MatchEntry { Virtual = Native.Str(m.VirtualName), Physical = Native.Str(m.PhysicalId), Vote = m.Vote });
                    }
                    return result;
                }
                finally { Native.annex_match_destroy(match); }
            }
            finally { Native.annex_scene_destroy(scene); }
        }

        IntPtr ScanScene(Frame frame, bool surfaces)
        {
            Native.Check(Native.annex_scan(Live, frame.Live, out IntPtr scene, out IntPtr e), e);
            if (!surfaces) return scene;
            try
            {
                Native.Check(Native.annex_scene_with_surfaces(scene, out IntPtr both, out e), e);
                return both;
            }
            finally { Native.annex_scene_destroy(scene); }
        }

        static List<PhysicalObject> Read(IntPtr scene)
        {
            var objects = new List<PhysicalObject>();
            int n = (int)Native.annex_scene_object_count(scene);
            for (int i = 0; i < n; ++i)
            {
                Native.Check(Native.annex_scene_object(scene, (UIntPtr)i, out Native.PhysObject o, out IntPtr e), e);
                var obj = new PhysicalObject { Id = Native.Str(o.Id), OnObject = Native.Str(Native.annex_scene_object_on(scene, (UIntPtr)i)) ?? "", PointCount = o.PointCount, Fit = o.Fit };
                for (int j = 0; j < o.PrimitiveCount; ++j)
                {
                    Native.Check(Native.annex_scene_primitive(scene, (UIntPtr)i, (UIntPtr)j, out Native.Primitive p, out e), e);
                    var prim = new PhysicalPrimitive
                    {
                        Shape = Native.Str(p.ShapeName),
                        Center = new Vec3(p.Cx, p.Cy, p.Cz),
                        Axis = new Vec3(p.Ax, p.Ay, p.Az),
                        Fit = p.Fit,
                    };
                    var x = new double[3];
                    if (Native.annex_scene_primitive_x_axis(scene, (UIntPtr)i, (UIntPtr)j, x) == 1) prim.XAxis = new Vec3(x[0], x[1], x[2]);
                    IntPtr[] names = { p.Name0, p.Name1, p.Name2 };
                    double[] dims = { p.D0, p.D1, p.D2 };
                    for (int d = 0; d < p.DimensionCount && d < 3; ++d) prim.Dimensions[Native.Str(names[d])] = dims[d];
                    obj.Primitives.Add(prim);
                }
                objects.Add(obj);
            }
            return objects;
        }
    }

    /// <summary>
    /// The render-loop object: Push() a frame each tick, then read Objects() and Events().
    /// With background scanning (the default) no push waits for a scan.
    /// </summary>
    public sealed class Session : Handle
    {
        Native.Object[] objects_ = new Native.Object[8];
        Native.Event[] events_ = new Native.Event[8];

        Session(IntPtr p) : base(p) { }
        protected override void Free(IntPtr p) => Native.annex_session_destroy(p);

        public static Session Create(Spec spec) => Create(spec, SessionParams.Defaults());

        public static Session Create(Spec spec, SessionParams p)
        {
            Native.Check(Native.annex_session_create(spec.Live, ref p, out IntPtr s, out IntPtr e), e);
            return new Session(s);
        }

        /// <summary>
        /// A session whose scan parameters all come from a scan config file (the camera's
        /// noise model, the supports, every threshold) in place of <c>p.Scan</c>, whose
        /// thread count alone still applies.
        /// </summary>
        public static Session Create(Spec spec, SessionParams p, string scanConfigPath) {
          Native.Check(Native.annex_session_create_with_scan_config(
                           spec.Live, ref p, scanConfigPath, out IntPtr s, out IntPtr e),
                       e);
          return new Session(s);
        }

        public void Push(Frame frame)
        {
            Native.Check(Native.annex_session_push(Live, frame.Live, out IntPtr e), e);
        }

        public FrameInfo Info
        {
            get
            {
                Native.Check(Native.annex_session_frame_info(Live, out FrameInfo info, out IntPtr e), e);
                return info;
            }
        }

        /// <summary>The annexed objects after the last push (two-call sizing, buffer reused).</summary>
        public List<AnnexedObject> Objects()
        {
            Native.Check(Native.annex_session_objects(Live, null, UIntPtr.Zero, out UIntPtr count, out IntPtr e), e);
            if (objects_.Length < (int)count) objects_ = new Native.Object[(int)count];
            Native.Check(Native.annex_session_objects(Ptr, objects_, (UIntPtr)objects_.Length, out count, out e), e);
            var list = new List<AnnexedObject>((int)count);
            for (int i = 0; i < (int)count; ++i)
            {
                Native.Object o = objects_[i];
                var sensor = new Pose
                {
                    Position = new Vec3(o.Px, o.Py, o.Pz),
                    Rotation = new Quat(o.Qx, o.Qy, o.Qz, o.Qw),
                    Scale = new Vec3(o.Sx, o.Sy, o.Sz),
                };
                list.Add(new AnnexedObject
                {
                    Virtual = Native.Str(o.VirtualName),
                    Physical = Native.Str(o.PhysicalId),
                    VirtualIndex = o.VirtualIndex,
                    State = (TrackingState)o.State,
                    Confidence = o.Confidence,
                    Vote = o.Vote,
                    MatchedFrame = o.MatchedFrame,
                    SensorPose = sensor,
                    UnityPose = Unity.FromSensor(sensor),
                });
            }
            return list;
        }

        /// <summary>What the last push changed: props annexed, lost, released.</summary>
        public List<AnnexEvent> Events()
        {
            Native.Check(Native.annex_session_events(Live, null, UIntPtr.Zero, out UIntPtr count, out IntPtr e), e);
            if (events_.Length < (int)count) events_ = new Native.Event[(int)count];
            Native.Check(Native.annex_session_events(Ptr, events_, (UIntPtr)events_.Length, out count, out e), e);
            var list = new List<AnnexEvent>((int)count);
            for (int i = 0; i < (int)count; ++i)
                list.Add(new AnnexEvent
                {
                    Kind = (EventKind)events_[i].Kind,
                    Virtual = Native.Str(events_[i].VirtualName),
                    Physical = Native.Str(events_[i].PhysicalId),
                    Frame = events_[i].Frame,
                });
            return list;
        }
    }

    /// <summary>Unity's conventions: left-handed, y up (the sensor frame mirrored in y).</summary>
    public static class Unity
    {
        public static Pose FromSensor(Pose sensor)
        {
            double[] p = { sensor.Position.X, sensor.Position.Y, sensor.Position.Z };
            double[] q = { sensor.Rotation.W, sensor.Rotation.X, sensor.Rotation.Y, sensor.Rotation.Z };
            var up = new double[3];
            var uq = new double[4];
            Native.annex_pose_to_unity(p, q, up, uq);
            return new Pose
            {
                Position = new Vec3(up[0], up[1], up[2]),
                Rotation = new Quat(uq[0], uq[1], uq[2], uq[3]),
                Scale = sensor.Scale,
            };
        }
    }
}

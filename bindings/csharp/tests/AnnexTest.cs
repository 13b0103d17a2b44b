// The C# binding under Mono, as the test suite runs it (test_csharp):
//   mono AnnexTest.exe SOURCE_DIR SHARED_DIR
// loads libannex_c (LD_LIBRARY_PATH), checks the ABI, reads specs (and a bad one's
// line:column), scans a real Kinect frame (skipped when SHARED_DIR/data/real is absent)
// and a bundled frame, then runs a session over samples/recordings/tabletop.
// Exits 0 when every check passed, 1 otherwise.
using System;
using System.Collections.Generic;
using System.IO;
using System.Linq;
using Annex;

static class AnnexTest
{
    static int failures = 0;

    static void Check(bool ok, string what)
    {
        Console.WriteLine((ok ? "ok   " : "FAIL ") + what);
        if (!ok) ++failures;
    }

    static int Main(string[] args)
    {
        if (args.Length != 2)
        {
            Console.Error.WriteLine("usage: AnnexTest.exe SOURCE_DIR SHARED_DIR");
            return 2;
        }
        string source = args[0], shared = args[1];
        try
        {
            Run(source, shared);
        }
        catch (Exception e)
        {
            Console.WriteLine("FAIL unexpected " + e.GetType().Name + ": " + e.Message);
            return 1;
        }
        Console.WriteLine(failures == 0 ? "all checks passed" : failures + " checks failed");
        return failures == 0 ? 0 : 1;
    }

    static void Run(string source, string shared)
    {
        Library.CheckAbi();
        Check(Library.Version == Environment.GetEnvironmentVariable("ANNEX_EXPECTED_VERSION"),
              "version " + Library.Version);

        // Specs.
        using (Spec study = Spec.Load(Path.Combine(source, "samples/specs/study.haptic")))
            Check(study.Names.Contains("champagne_bottle") && study.Names.Length == 7,
                  "study.haptic: " + string.Join(", ", study.Names));
        using (Spec units = Spec.Parse("annex-haptic 1\nobject duck\n  mesh duck.dae\n  model_scale 0.078\n  primitive body sphere\n    radius 0.05\n  end\nend\nobject cup\n  primitive body cylinder\n    radius 0.04\n    height 0.1\n  end\nend\n", "units.haptic"))
            Check(units.ModelScales.Length == 2 && Math.Abs(units.ModelScales[0] - 0.078) < 1e-12 && units.ModelScales[1] == 1.0,
                  "model scales: " + string.Join(", ", units.ModelScales));
        try
        {
            Spec.Parse("annex-haptic 1\nobject cup\n  primitive body cylinder\n    priority heavy\n  end\nend\n", "cup.haptic");
            Check(false, "a bad spec throws");
        }
        catch (AnnexException e)
        {
            Check(e.Status == Status.ParseError && e.Origin == "cup.haptic" && e.Line == 4 && e.Column > 0 &&
                  e.Message.StartsWith("cup.haptic:4:"), "bad spec: " + e.Message);
        }
        try
        {
            Spec.Load("/no/such/spec.haptic");
            Check(false, "a missing spec throws");
        }
        catch (AnnexException e)
        {
            Check(e.Status == Status.IoError, "missing spec: " + e.Message);
        }

        // Scans: a real Kinect frame (the milk carton, bleach and detergent bottles) and
        // the first recorded frame.
        using (Scanner scanner = Scanner.Create())
        {
            string real = Path.Combine(shared, "data/real/milk_cartoon_all_small_clorox.pcd");
            if (File.Exists(real))
            {
                using (Frame frame = Frame.LoadPcd(real))
                {
                    List<PhysicalObject> objects = scanner.Scan(frame);
                    Check(frame.Width == 640 && frame.Height == 480, "real frame is 640x480");
                    Check(objects.All(o => o.OnObject == ""), "real frame: every prop stands on the table");
                    Check(objects.Count >= 3 && objects.Any(o => o.Shape == "box") &&
                          objects.Count(o => o.Shape == "cylinder") >= 2,
                          "real frame: " + string.Join(", ", objects.Select(o => o.Id + " " + o.Shape)));
                }
            }
            else
            {
                Console.WriteLine("skip real Kinect frame: " + real + " not found (../shared is not checked out)");
            }
            using (Frame frame = Frame.LoadPcd(Path.Combine(source, "samples/recordings/tabletop/frame_0000.pcd")))
            {
                List<PhysicalObject> objects = scanner.Scan(frame);
                // A partial object cut by the image border is reported too, as unknown.
                var shapes = objects.Select(o => o.Shape).Where(s => s != "unknown").OrderBy(s => s).ToArray();
                Check(shapes.SequenceEqual(new[] { "cylinder", "sphere", "torus" }),
                      "recorded frame: " + string.Join(", ", shapes));
                PhysicalObject sphere = objects.FirstOrDefault(o => o.Shape == "sphere");
                Check(sphere != null && Math.Abs(sphere.Primitives[0].Dimensions["radius"] - 0.052) < 0.006,
                      "sphere radius about 5.2 cm");
                using (Spec study = Spec.Load(Path.Combine(source, "samples/specs/study.haptic")))
                {
                    var matches = scanner.Match(study, frame).Where(m => m.Physical != null)
                                         .ToDictionary(m => m.Virtual, m => m.Physical);
                    var shapeOf = objects.ToDictionary(o => o.Id, o => o.Shape);
                    Check(matches.Count == 2 && shapeOf[matches["champagne_bottle"]] == "cylinder" &&
                          shapeOf[matches["lamp"]] == "sphere" && !matches.ContainsKey("mug"),
                          "matches: " + string.Join(", ", matches.Select(kv => kv.Key + "->" + kv.Value)));
                }
                // The scan's flat surfaces follow its objects when asked for: the table's
                // free rectangle is a plane, and a keyboard panel matches it only then.
                List<PhysicalObject> withSurfaces = scanner.Scan(frame, true);
                Check(withSurfaces.Take(objects.Count).Select(o => o.Id).SequenceEqual(objects.Select(o => o.Id)) &&
                      objects.All(o => o.Shape != "plane"), "surfaces come after the objects");
                PhysicalObject free = withSurfaces.Skip(objects.Count).FirstOrDefault(o => o.Id == "s1.free");
                Check(free != null && free.Shape == "plane" && free.Primitives.Count == 1, "the table's free surface is a plane");
                if (free != null)
                {
                    PhysicalPrimitive plane = free.Primitives[0];
                    Vec3 x = plane.XAxis, n = plane.Axis;
                    Check(plane.Dimensions["size_x"] >= plane.Dimensions["size_y"] &&
                          Math.Abs(x.X * x.X + x.Y * x.Y + x.Z * x.Z - 1) < 1e-6 &&
                          Math.Abs(x.X * n.X + x.Y * n.Y + x.Z * n.Z) < 1e-6,
                          "the free surface's size_x side lies in its plane: " + x);
                }
                using (Spec keyboard = Spec.Parse("annex-haptic 1\nobject keyboard\n  primitive keys plane\n" +
                                                  "    size_x 0.50\n    size_y 0.12\n  end\nend\n", "keyboard.haptic"))
                {
                    Check(scanner.Match(keyboard, frame, true)[0].Physical == "s1.free" &&
                          scanner.Match(keyboard, frame)[0].Physical == null,
                          "the keyboard matches the table's free surface only among the surfaces");
                }
            }
            // A zero-pixel frame is refused with a message, not a crash.
            try
            {
                Frame.FromPoints(new float[0], 0, 0);
                Check(false, "an empty frame throws");
            }
            catch (AnnexException e)
            {
                Check(e.Status == Status.InvalidArgument, "empty frame: " + e.Message);
            }
        }

        // A scan config file (a RealSense's noise model, the supports) for a scanner and a
        // session; its errors name file:line:column.
        string conf =
            Path.Combine(Path.GetTempPath(), "annex-cs-" + Guid.NewGuid().ToString("N") + ".conf");
        try {
          File.WriteAllText(conf, "depth_noise stereo\nsupports s9\n");
          using (Scanner fromConfig = Scanner.FromConfig(conf)) using (
              Frame frame = Frame.LoadPcd(
                  Path.Combine(source, "samples/real/milk_cartoon_all_small_clorox.pcd"))) {
            try {
              fromConfig.Scan(frame);
              Check(false, "a support the frame lacks fails the scan");
            } catch (AnnexException e) {
              Check(e.Status == Status.ScanFailed && e.Message.Contains("no support 's9'"),
                    "the config's supports apply: " + e.Message);
            }
          }
          using (Spec study = Spec.Load(Path.Combine(source, "samples/specs/study.haptic"))) using (
              Session session = Session.Create(study, SessionParams.Defaults(), conf))
              Check(session != null, "a session from a scan config");
          File.WriteAllText(conf, "depth_noise stereo\ndepth_noise lidar\n");
          try {
            Scanner.FromConfig(conf);
            Check(false, "an unknown camera throws");
          } catch (AnnexException e) {
            Check(e.Status == Status.ParseError && e.Line == 2 && e.Column == 13 &&
                      e.Message.Contains("kinect, stereo, tof"),
                  "bad config: " + e.Message);
          }
        } finally {
          File.Delete(conf);
        }

        // Parameters are checked when the session is made.
        using (Spec study = Spec.Load(Path.Combine(source, "samples/specs/study.haptic")))
        {
            SessionParams bad = SessionParams.Defaults();
            bad.Scan.MaxHeightM = -1;
            try
            {
                Session.Create(study, bad);
                Check(false, "a negative max height throws");
            }
            catch (AnnexException e)
            {
                Check(e.Status == Status.InvalidArgument && e.Message.Contains("SessionParams.scan.max_height_m"),
                      "bad params: " + e.Message);
            }
        }

        // A background session over the bundled recording, as a render loop drives it.
        string[] files = Directory.GetFiles(Path.Combine(source, "samples/recordings/tabletop"), "frame_*.pcd")
                                  .OrderBy(f => f).ToArray();
        Check(files.Length == 4, "4 recorded frames");
        var annexed = new Dictionary<string, string>();
        int firstTracked = -1;
        using (Spec study = Spec.Load(Path.Combine(source, "samples/specs/study.haptic")))
        using (Session session = Session.Create(study))
        {
            // 60 pushes at 30 Hz, the recording played forwards and backwards: a background
            // scan finishes between pushes however loaded the machine is.
            int period = 2 * files.Length - 2;
            for (int k = 0; k < 60; ++k)
            {
                int f = k % period < files.Length ? k % period : period - k % period;
                using (Frame frame = Frame.LoadPcd(files[f]))
                    session.Push(frame);
                System.Threading.Thread.Sleep(33);
                FrameInfo info = session.Info;
                if (info.ScanApplied != 0 && info.ScanFrame >= k) Check(false, "a scan applied in its own push");
                foreach (AnnexEvent e in session.Events())
                    if (e.Kind == EventKind.Annexed) annexed[e.Virtual] = e.Physical;
                List<AnnexedObject> objects = session.Objects();
                if (objects.Count > 0 && firstTracked < 0) firstTracked = k;
                foreach (AnnexedObject o in objects)
                {
                    Pose s = o.SensorPose, u = o.UnityPose;
                    double qn = Math.Sqrt(s.Rotation.X * s.Rotation.X + s.Rotation.Y * s.Rotation.Y +
                                          s.Rotation.Z * s.Rotation.Z + s.Rotation.W * s.Rotation.W);
                    bool sane = Math.Abs(qn - 1) < 1e-9 && s.Position.Z > 0.3 && s.Position.Z < 3 &&
                                u.Position.Y == -s.Position.Y && u.Position.X == s.Position.X &&
                                u.Rotation.W == s.Rotation.W && u.Rotation.Y == s.Rotation.Y &&
                                u.Rotation.X == -s.Rotation.X && o.Confidence >= 0 && o.Confidence <= 1 &&
                                (o.State == TrackingState.Tracking || o.State == TrackingState.Reinit);
                    if (!sane) Check(false, "frame " + k + " " + o.Virtual + " at " + s.Position + " state " + o.State);
                }
            }
            List<AnnexedObject> last = session.Objects();
            Check(firstTracked >= 1, "annexed from push " + firstTracked + " (a scan applies a push later)");
            Check(last.Count == 2 && annexed.Count == 2 &&
                  new[] { "champagne_bottle", "lamp" }.All(n => annexed.ContainsKey(n)),
                  "session annexed: " + string.Join(", ", annexed.Select(kv => kv.Key + "->" + kv.Value)));
            Check(last.All(o => annexed[o.Virtual] == o.Physical), "props kept their ids");
        }
    }
}

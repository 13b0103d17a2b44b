// Runs docs/streaming.md's AnnexReceiver outside Unity: binds it to the given port (0: one
// the OS picks, printed as "listening <port>" so that concurrent runs never share one) with
// the bound objects, calls Update as Unity would until frame `last` arrived (or 60 s
// passed), then prints each object's state:
//   object <name> active=<0|1> p=x,y,z q=x,y,z,w s=x,y,z
using System;
using System.Collections.Generic;
using System.Globalization;
using System.Reflection;
using System.Threading;
using UnityEngine;

public static class ReceiverDriver
{
    static void Call(object target, string method)
    {
        target.GetType().GetMethod(method, BindingFlags.Instance | BindingFlags.NonPublic | BindingFlags.Public)
            .Invoke(target, null);
    }

    public static int Main(string[] args)
    {
        int port = int.Parse(args[0]);
        int last = int.Parse(args[1]);
        var receiver = new AnnexReceiver { port = port, sensor = new Transform() };
        var names = new List<string>();
        for (int i = 2; i < args.Length; ++i)
        {
            names.Add(args[i]);
            receiver.objects.Add(new AnnexReceiver.VirtualObjectBinding { virtualName = args[i], target = new GameObject(args[i]) });
        }
        Call(receiver, "OnEnable");
        var socket = (System.Net.Sockets.UdpClient)receiver.GetType()
            .GetField("socket", BindingFlags.Instance | BindingFlags.NonPublic | BindingFlags.Public)
            .GetValue(receiver);
        Console.WriteLine("listening " + ((System.Net.IPEndPoint)socket.Client.LocalEndPoint).Port);
        Console.Out.Flush();
        var deadline = DateTime.UtcNow.AddSeconds(60);
        while (receiver.LastFrame < last && DateTime.UtcNow < deadline)
        {
            Call(receiver, "Update");
            Thread.Sleep(5);
        }
        Call(receiver, "Update");
        Call(receiver, "OnDisable");
        var c = CultureInfo.InvariantCulture;
        Console.WriteLine("last_frame " + receiver.LastFrame);
        foreach (var b in receiver.objects)
        {
            var t = b.target.transform;
            Console.WriteLine(string.Format(c, "object {0} active={1} p={2:R},{3:R},{4:R} q={5:R},{6:R},{7:R},{8:R} s={9:R},{10:R},{11:R}",
                b.virtualName, b.target.activeSelf ? 1 : 0, t.position.x, t.position.y, t.position.z,
                t.rotation.x, t.rotation.y, t.rotation.z, t.rotation.w, t.localScale.x, t.localScale.y, t.localScale.z));
        }
        return receiver.LastFrame >= last ? 0 : 1;
    }
}

// Counts the messages Java's LCM receives on one channel, with or without
// the receive buffer fix (tests of tools/lcm-spy's fix, headless).
//   java evade.tools.Probe URL CHANNEL SECONDS FIX(0|1)
// prints: "<messages> <bytes of the last message> <granted buffer or -1>"
package evade.tools;

import java.util.concurrent.atomic.AtomicInteger;

public final class Probe {
  private Probe() {}

  public static void main(String[] args) throws Exception {
    String url = args[0];
    String channel = args[1];
    double seconds = Double.parseDouble(args[2]);
    boolean fix = args[3].equals("1");
    lcm.lcm.LCM lcm = new lcm.lcm.LCM(url);
    int granted = fix ? ReceiveBuffer.apply(lcm, ReceiveBuffer.fromUrl(url)) : -1;
    AtomicInteger count = new AtomicInteger();
    AtomicInteger size = new AtomicInteger();
    lcm.subscribe(channel, (l, ch, in) -> {
      size.set(in.available());
      count.incrementAndGet();
    });
    System.out.println("ready");
    System.out.flush();
    Thread.sleep((long) (seconds * 1000));
    System.out.println(count.get() + " " + size.get() + " " + granted);
    System.out.flush();
    System.exit(0);
  }
}

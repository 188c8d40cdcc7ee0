// The window's help (F1): how to move the instrument, and what the lesson being
// taken asks (probing and charting, or the oral inspection).
#include "ui/main_window.h"

namespace sulcus::ui {

QString MainWindow::HelpHtml(std::optional<HelpTopic> topic) const {
  if (!topic)
    topic = lesson_spec_ && lesson_spec_->inspection() ? HelpTopic::kInspection
                                                       : HelpTopic::kProbing;
  const QString moving =
      "<b>Moving the instrument</b> (mouse and keyboard), as seen on the screen: D/A "
      "right and left, W/S up and down, Q/E into and out of the screen, 0.1 mm a press "
      "(hold Alt for 0.02 mm); with Shift they turn it about its tip. "
      "<b>N</b> places the probe over the next site, along the tooth leaned 4 degrees "
      "out from it (practice). "
      "<b>The press</b>: R pushes the probe down its own axis with 0.02 N more each "
      "press, F with 0.02 N less, X lets go: the tip goes down until the tissue answers "
      "with that force, so 0.24 N holds it at the pocket floor (the white mark on the "
      "gauge). <b>Walking</b>: with the tip in a sulcus, comma and period move it along "
      "the sulcus 0.4 mm (left and right on the screen) while the press keeps it down. "
      "<b>T</b> at an interdental site tilts the probe 20 degrees away from the contact "
      "about its tip, so the tip goes under the contact point into the col; T again "
      "stands it back along the tooth. "
      "Reset tool lifts it 6 mm above the site. Ctrl + drag moves it with the mouse, "
      "Ctrl + wheel pushes it. Drag without Ctrl turns the camera, the wheel zooms; "
      "the View buttons and Look at tooth place it.";
  if (*topic == HelpTopic::kInspection)
    return moving +
           "<br><br><b>The examination</b>: follow the steps in their order (lips, "
           "cheeks, gingiva, tongue, floor of "
           "the mouth, palate, then tooth by tooth). A region or surface counts as "
           "examined when the tip rests on it "
           "for a moment; a tooth surface counts as seen when the camera has shown it (a "
           "neighbouring tooth can hide "
           "it: turn the camera round). Touch gently: soft tissue pressed above its "
           "limit, or a carious lesion "
           "pressed above 0.5 N, is scored as damage.<br><br><b>Recording findings</b> "
           "on the odontogram: click a tooth to select it, then a "
           "surface of the selected tooth for caries, <i>Ca</i> for calculus, <i>G</i> "
           "for inflamed "
           "gingiva; right-click a tooth "
           "for its WHO status; click a soft-tissue region to record a lesion there. "
           "Keys: arrows choose the tooth, "
           "M D B L O mark caries on a surface, C calculus, G inflamed gingiva, 0-9 the "
           "WHO status. Press a key "
           "again to take the finding back.<br><br><b>Finishing</b>: Submit the findings "
           "ends the examination (you "
           "may still correct a finding); Lesson &gt; Finish shows your report.";
  return moving +
         "<br><br><b>Probing</b>: walk the probe around each tooth in short up-and-down "
         "strokes with the tip on the "
         "tooth, parallel to the long axis; at the contacts tilt it into the col. Press "
         "the pocket floor lightly: the "
         "gauge's green band is the force the lesson gives full credit "
         "for.<br><br><b>Charting</b>: click the chart (or "
         "press Tab to it), type the "
         "depth you read at each site in whole millimetres; it moves to the next site "
         "along the path. B or Space "
         "marks bleeding on the site you just entered; Backspace goes "
         "back. Depths of 10 mm and more: + then the second digit (+ 2 is 12 mm); a "
         "depth over 12 mm asks you to confirm it with Enter. You may chart a site with "
         "the probe still at its floor: that is its reading. Rows: PD, GM (the gingival "
         "margin, positive for recession), CAL = PD + GM, all in mm; in practice the "
         "true PD of each site you probed."
         "<br><br><b>Diagnosis</b>: at the end, "
         "Lesson &gt; Declare the diagnosis; then Lesson &gt; Finish shows your report.";
}

}  // namespace sulcus::ui
